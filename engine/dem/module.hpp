// The DEM module: grains, contacts, walls and the neighbour search.
#pragma once

#include "silt/module.hpp"

namespace silt::dem {

const ModuleSpec& module();

// Its parts, in dem/.
std::vector<KeySpec> dem_keys();
std::vector<ObservableSpec> dem_observables();
void compile_dem(const SceneDesc& d, Model& m);
void finish_dem(const SceneDesc& d, Model& m);
std::string describe_dem(const Model& m);
// After grains were frozen (Simulation::freeze): the counts, the system's fingerprint, the mass
// scales and the energy scale that depend on which grains are free.
void refresh_frozen(Model& m);

}  // namespace silt::dem
