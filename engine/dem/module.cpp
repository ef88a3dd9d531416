// The DEM module as the rest of silt sees it (silt/module.hpp).
#include "dem/module.hpp"

#include <algorithm>

#include "dem/forces_under.hpp"

namespace silt::dem {
namespace {

std::string steer_dem(Model& m, const Model& fresh) {
  m.contact.friction = fresh.contact.friction;
  for (size_t w = 0; w < m.walls.size(); ++w) m.walls[w].friction = fresh.walls[w].friction;
  m.materials = fresh.materials;
  m.pair_contact = fresh.pair_contact;
  m.wall_contact = fresh.wall_contact;
  // The energy the scene can supply under what was steered (a gravity, a pressure), kept at the
  // most it has been: a grain falling under g = 5e5 set while running failed the energy check
  // against the 9.81's supply, where the same scene from its file failed on the impact's overlap.
  m.limits.energy_scale = std::max(m.limits.energy_scale, fresh.limits.energy_scale);
  m.limits.energy_per_s = std::max(m.limits.energy_per_s, fresh.limits.energy_per_s);
  m.limits.energy_per_s2 = std::max(m.limits.energy_per_s2, fresh.limits.energy_per_s2);
  return "";
}

// The grains `freeze` froze in the running model, frozen in the one compiled again (only when
// they are the same grains: else the fingerprints differ anyway). Not the grains the scene froze:
// `set grains.0.frozen false` unfreezes those.
void carry_frozen(Model& fresh, const Model& m) {
  const std::vector<uint8_t>& by_freeze = m.init.frozen_by_freeze;
  if (by_freeze.empty() || fresh.init.frozen.size() != by_freeze.size()) return;
  for (size_t i = 0; i < by_freeze.size(); ++i) fresh.init.frozen[i] |= by_freeze[i];
  fresh.init.frozen_by_freeze = by_freeze;
  refresh_frozen(fresh);
}

}  // namespace

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "dem";
    s.doc = "soft-sphere grains: contact laws, walls, neighbour lists, velocity Verlet";
    s.keys = dem_keys();
    mark_initial(s.keys,
                 {"grains[].velocity", "grains[].temperature", "grains[].velocities", "grains[].angular_velocities"});
    s.observables = dem_observables();
    // Grains make the DEM; a scene of a fluid alone has none.
    s.enabled = [](const SceneDesc& d) { return d.group_count("grains") > 0 || !d.has_table("fluid"); };
    s.compile = compile_dem;
    s.finish = finish_dem;
    s.describe = describe_dem;
    s.steer = steer_dem;
    s.fields = {{"dem_forces_under", Extent::kFree, "",
                 "the parameters of every force on the grains that particle_f and the pair and wall forces were made "
                 "under (dem/forces_under.hpp): others in the model make them again before the step; the first "
                 "state's forces, refresh_forces"},
                {"dem_compression", Extent::kFree, "",
                 "[1] in a state of the dry compression that prepares a packing (prepare.compress) before its end: "
                 "the compression's last good state, which a restore goes on compressing; empty otherwise"}};
    s.force_parameters = contact_parameters;
    s.stale = forces_under_other;
    s.carry = carry_frozen;
    return s;
  }();
  return spec;
}

}  // namespace silt::dem
