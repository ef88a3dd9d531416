#include "silt/errors.hpp"

namespace silt {

std::string FileLoc::str() const {
  std::string s = file.empty() ? std::string("<scene>") : file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (col > 0) s += ":" + std::to_string(col);
  }
  return s;
}

static std::string located(const FileLoc& loc, const std::string& message) { return loc.str() + ": " + message; }

SceneError::SceneError(FileLoc loc, const std::string& message)
    : std::runtime_error(located(loc, message)), loc_(std::move(loc)), message_(message) {}

}  // namespace silt
