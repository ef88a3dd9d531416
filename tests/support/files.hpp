// Reading a file whole in tests.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

namespace silt::test {

// The bytes of a file ("" when it cannot be read).
inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace silt::test
