// Live steering: a changed value applied to a compiled model between two steps.
#include "silt/model.hpp"

namespace silt {

std::string steer(Model& m, const Override& change) {
  SceneDesc desc = m.desc;
  try {
    apply_override(desc, change);
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
