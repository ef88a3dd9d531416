#include "shell/scene_loading.hpp"

#include <iostream>

#include "shell/commands.hpp"

namespace silt::cli {

int report_error(const std::string& message, int code) {
  std::cerr << "silt: " << message << "\n";
  return code;
}

std::optional<Model> load_model(const std::string& scene, const std::vector<std::string>& sets, int& code,
                                const std::optional<Override>& length) {
  try {
    std::vector<Override> overrides;
    for (const std::string& s : sets) overrides.push_back(parse_override(s));
    SceneDesc desc = load_scene_file(scene, overrides);
    if (!length) return compile(desc);
    SceneDesc replaced = desc;
    apply_override(replaced, *length);
    Model m = compile(replaced);
    m.desc = std::move(desc);  // the scene as given: what checkpoints record and a restore compares
    return m;
  } catch (const SceneError& e) {
    code = report_error(e.what(), static_cast<int>(ExitCode::kScene));
  } catch (const IoError& e) {
    code = report_error(e.what(), static_cast<int>(ExitCode::kIo));
  }
  return std::nullopt;
}

}  // namespace silt::cli
