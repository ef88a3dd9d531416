// Initial grains of a scene: radii, placement and velocities of every [[grains]] table.
#pragma once

#include "silt/model.hpp"

namespace silt::dem {

// Fills m.init, m.n_grains, m.n_frozen, m.group_names and the radius/mass statistics.
// Requires m.dim, m.box and m.walls. Throws SceneError at the offending key.
void setup_grains(const SceneDesc& d, Model& m);

// Refuses, at its key, a group placed "explicit" whose positions are missing, empty or not of dim
// coordinates each. Before the contact law is read: a scene that gives no contact.k_n of its own
// then needs its grains' (such a scene was refused as missing contact.k_n).
void check_explicit_positions(const SceneDesc& d, int dim);

// The key that gives group g's sizes (radius, radius_min, ..., frozen_from): where a mass made of
// them is refused.
std::string grain_size_key(const SceneDesc& d, int g);

// The key to blame for a mass out of the numbers' range made of a radius r and group g's density:
// the density when it is the factor farther from 1 (a density of 1e-300 by --set was located at
// the scene's radius line), else the sizes' key.
std::string grain_mass_key(const SceneDesc& d, int g, int dim, double r);

// Refuse overlaps beyond limits.max_overlap at t = 0 (grain-grain and grain-wall).
void check_initial_overlaps(const Model& m);

}  // namespace silt::dem
