// Fixtures of the command-line tests: the `silt` binary run with arguments, its exit code and
// what it printed; files written and read.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "support/files.hpp"
#include "support/scenes.hpp"

namespace silt::test {

struct Result {
  int code = -1;
  std::string out;  // stdout and stderr
};

// A command line run by /bin/sh, stdout and stderr captured; the exit code a signal gave is
// 128 + the signal.
inline Result sh(const std::string& command) {
  Result r;
  const std::string cmd = "{ " + command + "; } 2>&1";
  std::FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : (WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1);
  return r;
}

// `silt ARGS` through the shell (redirections allowed in ARGS).
inline Result silt_cli(const std::string& args) { return sh(silt_binary() + " " + args); }

inline std::string write_file(const std::string& name, const std::string& text) {
  std::ofstream(name) << text;
  return name;
}

}  // namespace silt::test
