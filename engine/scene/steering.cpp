// Live steering: a changed value applied to a compiled model between two steps.
#include <algorithm>

#include "silt/model.hpp"

namespace silt {
namespace {

// Keys that are alternatives to one another: a scene gives keys of at most one side of each
// group, and compile() refuses two sides ("give run.dt or run.dt_over_tc, not both"). A change
// to a key of one side replaces the keys of the other sides.
using Side = std::vector<std::string>;
const std::vector<std::vector<Side>>& alternatives() {
  static const std::vector<std::vector<Side>> groups = {
      {{"run.dt"}, {"run.dt_over_tc"}},
      {{"run.steps"}, {"run.time"}},
      {{"gravity.vector"}, {"gravity.magnitude", "gravity.angle"}},
      {{"shear.rate"}, {"shear.inertial_number"}, {"shear.stress"}},
  };
  return groups;
}

}  // namespace

void apply_change(SceneDesc& desc, const Override& change, const std::string& where) {
  try {
    apply_override(desc, change);
  } catch (const SceneError& e) {
    throw SceneError(FileLoc{where, 0, 0}, e.message());
  }
  // The value typed is named by what was typed, also in the errors compile() finds with it.
  if (auto it = desc.entries.find(change.key); it != desc.entries.end()) it->second.loc = FileLoc{where, 0, 0};
  for (const auto& group : alternatives())
    for (const Side& side : group) {
      if (std::find(side.begin(), side.end(), change.key) == side.end()) continue;
      for (const Side& other : group)
        if (&other != &side)
          for (const std::string& key : other) desc.entries.erase(key);
    }
}

std::string steer(Model& m, const Override& change) {
  SceneDesc desc = m.desc;
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
  if (fresh.scene_hash != m.scene_hash) return "'" + change.key + "' would change the grains";
  if (fresh.shear.on != m.shear.on || fresh.shear.stress_controlled != m.shear.stress_controlled)
    return "'" + change.key + "' would switch the shear on or off, or between imposed rate and imposed stress: set it when stopped";
  // The steerable parts of a Model.
  m.gravity = fresh.gravity;
  m.contact.friction = fresh.contact.friction;
  for (size_t w = 0; w < m.walls.size(); ++w) m.walls[w].friction = fresh.walls[w].friction;
  m.dt = fresh.dt;
  m.box_control.pressure = fresh.box_control.pressure;
  m.box_control.mass_factor = fresh.box_control.mass_factor;
  m.box_control.mass = fresh.box_control.mass;
  m.render = fresh.render;
  m.shear.rate = fresh.shear.rate;
  m.shear.stress = fresh.shear.stress;
  m.desc = std::move(fresh.desc);
  return "";
}

}  // namespace silt
