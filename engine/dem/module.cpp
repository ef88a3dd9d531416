// The DEM module as the rest of silt sees it (silt/module.hpp).
#include "dem/module.hpp"

namespace silt::dem {
namespace {

std::string steer_dem(Model& m, const Model& fresh) {
  m.contact.friction = fresh.contact.friction;
  for (size_t w = 0; w < m.walls.size(); ++w) m.walls[w].friction = fresh.walls[w].friction;
  m.materials = fresh.materials;
  m.pair_contact = fresh.pair_contact;
  m.wall_contact = fresh.wall_contact;
  return "";
}

// The grains `freeze` froze in the running model, frozen in the one compiled again (only when
// they are the same grains: else the fingerprints differ anyway).
void carry_frozen(Model& fresh, const Model& m) {
  if (fresh.init.frozen.size() != m.init.frozen.size() || fresh.init.frozen == m.init.frozen) return;
  for (size_t i = 0; i < m.init.frozen.size(); ++i) fresh.init.frozen[i] |= m.init.frozen[i];
  refresh_frozen(fresh);
}

}  // namespace

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "dem";
    s.doc = "soft-sphere grains: contact laws, walls, neighbour lists, velocity Verlet";
    s.keys = dem_keys();
    s.observables = dem_observables();
    // Grains make the DEM; a scene of a fluid alone has none.
    s.enabled = [](const SceneDesc& d) { return d.group_count("grains") > 0 || !d.has_table("fluid"); };
    s.compile = compile_dem;
    s.finish = finish_dem;
    s.describe = describe_dem;
    s.steer = steer_dem;
    s.carry = carry_frozen;
    return s;
  }();
  return spec;
}

}  // namespace silt::dem
