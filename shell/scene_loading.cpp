#include "shell/scene_loading.hpp"

#include <iostream>

#include "shell/commands.hpp"

namespace silt::cli {

int report_error(const std::string& message, int code) {
  std::cerr << "silt: " << message << "\n";
  return code;
}

std::optional<Model> load_model(const std::string& scene, const std::vector<std::string>& sets, int& code) {
  try {
    std::vector<Override> overrides;
    for (const std::string& s : sets) overrides.push_back(parse_override(s));
    return compile(load_scene_file(scene, overrides));
  } catch (const SceneError& e) {
    code = report_error(e.what(), static_cast<int>(ExitCode::kScene));
  } catch (const IoError& e) {
    code = report_error(e.what(), static_cast<int>(ExitCode::kIo));
  }
  return std::nullopt;
}

}  // namespace silt::cli
