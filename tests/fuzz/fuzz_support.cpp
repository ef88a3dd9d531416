#include "fuzz_support.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace silt::fuzz {
namespace {

std::string g_scratch;

void remove_scratch() {
  std::error_code ec;
  if (!g_scratch.empty()) std::filesystem::remove_all(g_scratch, ec);
}

// Kept for the whole run (libFuzzer holds on to its arguments): never freed, always reachable.
std::deque<std::string>* g_args = new std::deque<std::string>;

char* absolute_copy(const std::string& prefix, const std::string& path) {
  std::string abs = std::filesystem::absolute(path).string();
  if (path.ends_with('/') && !abs.ends_with('/')) abs += '/';  // a prefix stays a directory prefix
  return g_args->emplace_back(prefix + abs).data();
}

}  // namespace

void enter_scratch_dir(int* argc, char*** argv) {
  // Flags whose value is a path; every argument that is not a flag is a corpus or an input.
  static const char* const kPathFlags[] = {"-artifact_prefix=",    "-exact_artifact_path=", "-dict=",
                                           "-merge_control_file=", "-features_dir=",        "-data_flow_trace="};
  static auto* args = new std::vector<char*>;
  bool prefix = false;
  for (int k = 0; k < *argc; ++k) {
    const std::string a = (*argv)[k];
    char* out = (*argv)[k];
    if (k > 0 && !a.starts_with("-")) out = absolute_copy("", a);
    for (const char* flag : kPathFlags)
      if (a.starts_with(flag) && a.size() > std::strlen(flag)) {
        out = absolute_copy(flag, a.substr(std::strlen(flag)));
        prefix = prefix || std::strcmp(flag, "-artifact_prefix=") == 0;
      }
    args->push_back(out);
  }
  if (!prefix) args->push_back(absolute_copy("-artifact_prefix=", "./"));
  args->push_back(nullptr);
  *argc = static_cast<int>(args->size()) - 1;
  *argv = args->data();

  // In memory where there is a tmpfs: sessions make and remove files at every input.
  const char* tmp = std::getenv("TMPDIR");
  std::error_code ec;
  const std::string base = tmp && *tmp ? tmp : std::filesystem::is_directory("/dev/shm", ec) ? "/dev/shm" : "/tmp";
  std::string dir = base + "/silt_fuzz_XXXXXX";
  if (!mkdtemp(dir.data()) || chdir(dir.c_str()) != 0) {
    std::perror("silt fuzz: scratch directory");
    std::exit(1);
  }
  g_scratch = dir;
  std::atexit(remove_scratch);
}

std::string source_path(const std::string& relative) { return std::string(SILT_SOURCE_DIR) + "/" + relative; }

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) bug("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) bug("cannot write " + path);
}

void bug(const std::string& what) {
  std::fprintf(stderr, "silt fuzz: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace silt::fuzz
