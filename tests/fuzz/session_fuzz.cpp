// libFuzzer target for whole shell sessions without a terminal, as `silt shell` reads a pipe
// (shell/repl.cpp, plain_lines): the first byte picks the scene loaded first, the rest is split
// into lines (a control character is part of its line, a final line needs no newline), at most
// kMaxSessionLines of them, each made bounded and executed by a Session (session_driver.hpp).
// Seeds: the shipped scripts (scenes/*.silt) and tests/fuzz/seeds/*.silt.
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "session_driver.hpp"

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  silt::fuzz::enter_scratch_dir(argc, argv);
  silt::fuzz::prepare_sessions();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  silt::fuzz::SessionDriver driver(data[0]);
  std::string buf(reinterpret_cast<const char*>(data) + 1, size - 1);
  while (!buf.empty()) {
    const auto nl = buf.find('\n');
    std::string line = buf.substr(0, nl);
    buf.erase(0, nl == std::string::npos ? buf.size() : nl + 1);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!driver.line(line)) break;
  }
  return 0;
}
