// Fixtures of the shell tests: a session driven command by command with its output captured,
// a scratch directory, a scene whose runs fail.
#pragma once

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "shell/session.hpp"

namespace silt::test {

struct Fixture {
  std::ostringstream out, err;
  shell::Session s{out, err, 2};
  bool run(const std::string& line) { return s.execute(line); }
  std::string take_out() { return take(out); }
  std::string take_err() { return take(err); }
  static std::string take(std::ostringstream& o) {
    std::string text = o.str();
    o.str("");
    return text;
  }
  // The value `print OBS` shows (the number after "=", its unit after it).
  double value(const std::string& obs) {
    take_out();
    REQUIRE(run("print " + obs));
    const std::string o = take_out();
    return std::stod(o.substr(o.find('=') + 1));
  }
  // The state's hash (the `hash` command): equal hashes, bitwise equal states.
  std::string hash() {
    take_out();
    REQUIRE(run("hash"));
    const std::string o = take_out();
    REQUIRE(o.rfind("state hash ", 0) == 0);
    return o.substr(11, 16);
  }
};

// A fresh directory under the system's temporary one, removed with what it holds.
class TempDir {
 public:
  TempDir() {
    std::string name = (std::filesystem::temp_directory_path() / "silt_test_XXXXXX").string();
    REQUIRE(::mkdtemp(name.data()) != nullptr);
    path_ = name;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Two soft grains thrown at each other: the run fails (overlap past limits.max_overlap).
inline const char* kSoftCollision = R"(
[scene]
dimension = 3
[domain]
lo = [-5, -5, -5]
hi = [5, 5, 5]
[contact]
model = "hooke"
k_n = 100
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[-1, 0, 0], [1, 0, 0]]
velocity = "explicit"
velocities = [[10, 0, 0], [-10, 0, 0]]
[run]
dt = 1e-3
)";

}  // namespace silt::test
