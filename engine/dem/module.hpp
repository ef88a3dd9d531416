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
// Bytes n grains of this model take, their pairs and cells included (an estimate from the field
// list and a dense packing); refuse (at `key`) a scene that would not fit in the machine.
double grains_memory_bytes(const Model& m, int64_t n);
void check_memory(const SceneDesc& d, const Model& m, int64_t n, const std::string& key);
// After grains were frozen (Simulation::freeze): the counts, the system's fingerprint, the mass
// scales and the energy scale that depend on which grains are free.
void refresh_frozen(Model& m);

}  // namespace silt::dem
