// Live steering: a changed value applied to a compiled model between two steps.
#include "silt/module.hpp"

namespace silt {

void apply_change(SceneDesc& desc, const Override& change, const std::string& where) {
  try {
    apply_override(desc, change);
  } catch (const SceneError& e) {
    throw SceneError(FileLoc{where, 0, 0}, e.message());
  }
  // The value typed is named by what was typed, also in the errors compile() finds with it.
  if (auto it = desc.entries.find(change.key); it != desc.entries.end()) it->second.loc = FileLoc{where, 0, 0};
  desc.erase_alternatives_of(change.key);
}

std::string steer(Model& m, const Override& change, const SceneDesc* scene) {
  SceneDesc desc = scene ? *scene : m.desc;
  try {
    apply_change(desc, change, change.key);
  } catch (const SceneError& e) {
    return e.message();
  }
  const KeySpec* spec = find_key_spec(normalise_key(change.key));
  // apply_override accepted the key, so it has a spec; "grains.0.x" style keys normalise too.
  if (!spec || !spec->steerable) return "'" + change.key + "' cannot change during a run (it is not steerable)";
  Model fresh;
  try {
    fresh = compile(desc);
  } catch (const SceneError& e) {
    return e.message();
  }
  // (after `freeze`, every change was refused: the scene has no frozen grains)
  if (!carry_running(fresh, m)) return "'" + change.key + "' would change the grains";
  if (fresh.modules != m.modules) return "'" + change.key + "' would turn a module on or off: set it when stopped";
  // Each module takes over its steerable parts, or refuses; the model changes only if none does.
  Model next = m;
  for (const Module& mod : modules()) {
    if (!mod.spec->steer || !m.module_on(mod.spec->name)) continue;
    if (std::string why = mod.spec->steer(next, fresh); !why.empty()) return "'" + change.key + "': " + why;
  }
  next.params = fresh.params;
  next.desc = std::move(fresh.desc);
  m = std::move(next);
  return "";
}

}  // namespace silt
