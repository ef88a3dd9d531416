// Reading and compiling a scene for a subcommand, with errors mapped to exit codes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "silt/model.hpp"

namespace silt::cli {

// On error prints "silt: file:line:col: message" and sets `code` (2 scene, 4 I/O).
std::optional<Model> load_model(const std::string& scene, const std::vector<std::string>& sets, int& code);

}  // namespace silt::cli
