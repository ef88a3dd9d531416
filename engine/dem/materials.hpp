// Materials: grains of different [[grains]] groups, and walls, may be made of different stuff.
// A contact between two materials takes the scene's law with parameters mixed from theirs:
//
//   Hertz modulus (Peyneau's E~ of eq. 1.22, F = (E~/3) sqrt(2 R_eq) h^(3/2)):
//     E~_ij = 2 / (c_i + c_j),  c = (1 - nu^2) / E    (Johnson 1985 eq. 4.22, E~ = 2 E*),
//     which is E/(1 - nu^2) for one material and twice that against a rigid wall (c = 0);
//   linear springs (hooke, linear): in series, k_ij = 2 k_i k_j / (k_i + k_j);
//   Coulomb friction: the smaller coefficient, min(mu_i, mu_j) (the weaker surface slips; YADE's
//     FrictMat takes the same).
//
// The spring-dashpot law (restitution and contact time) is a property of a pair, not of a
// material: its groups share the scene's.
#pragma once

#include <cmath>

#include <algorithm>

#include "silt/model.hpp"

namespace silt::dem {

inline double hertz_pair_modulus(double ci, double cj) { return 2.0 / (ci + cj); }
// (where 2 ki kj / (ki + kj) overflows or underflows, springs of 1e200 or 1e-200, as
// lo (2 / (1 + lo / hi)); the same bits elsewhere)
inline double series_stiffness(double ki, double kj) {
  const double k = 2.0 * ki * kj / (ki + kj);
  if (k > 0 && k < HUGE_VAL) return k;
  const double lo = ki < kj ? ki : kj, hi = ki < kj ? kj : ki;
  return lo * (2.0 / (1.0 + lo / hi));
}
inline double pair_friction(double a, double b) { return std::min(a, b); }

// The contact law between two materials: the scene's, its modulus, stiffness and friction mixed.
ContactParams mix(const ContactParams& scene, const Material& a, const Material& b);

// Reads grains[].young_modulus, poisson_ratio, k_n, friction and walls[].young_modulus,
// poisson_ratio, rigid, k_n, friction into m.materials, m.pair_contact and m.wall_contact (after
// the contact law and the walls are read).
void setup_materials(const SceneDesc& d, Model& m);

}  // namespace silt::dem
