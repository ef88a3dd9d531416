// Reading and compiling a scene for a subcommand, with errors mapped to exit codes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "silt/model.hpp"
#include "silt/scene.hpp"

namespace silt::cli {

// On error prints "silt: file:line:col: message" and sets `code` (2 scene, 4 I/O). `length`: a
// key that replaces the scene's [run] length before it is compiled (as the shell's `set` replaces
// an alternative), for a length given on the command line.
std::optional<Model> load_model(const std::string& scene, const std::vector<std::string>& sets, int& code,
                                const std::optional<Override>& length = std::nullopt);

}  // namespace silt::cli
