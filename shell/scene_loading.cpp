#include "shell/scene_loading.hpp"

#include <algorithm>
#include <iostream>

#include "shell/commands.hpp"

namespace silt::cli {

int report_error(const std::string& message, int code) {
  std::cerr << "silt: " << message << "\n";
  return code;
}

namespace {

// The file's values a --set replaced, by the key set (the shell's `set` says the same; the command
// line dropped a scene's fluid.dt under --set fluid.dt_max without a word).
void note_replaced(const SceneDesc& d) {
  std::vector<std::string> done;
  for (const auto& entry : d.replaced) {
    const std::string& by = entry.second;
    if (std::find(done.begin(), done.end(), by) != done.end()) continue;
    done.push_back(by);
    std::vector<std::string> keys;
    for (const auto& other : d.replaced)
      if (other.second == by) keys.push_back(other.first);
    std::cerr << "silt: note: --set " << by << " replaces the scene's";
    for (size_t k = 0; k < keys.size(); ++k) std::cerr << (k ? ", " : " ") << keys[k];
    std::cerr << (keys.size() == 1 ? ", an alternative to it\n" : ", alternatives to it\n");
  }
}

}  // namespace

std::optional<Model> load_model(const std::string& scene, const std::vector<std::string>& sets, int& code,
                                const std::optional<Override>& length) {
  try {
    std::vector<Override> overrides;
    for (const std::string& s : sets) overrides.push_back(parse_override(s));
    SceneDesc desc = load_scene_file(scene, overrides);
    note_replaced(desc);
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
