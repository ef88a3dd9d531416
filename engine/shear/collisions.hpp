// Collisions in a flow sheared at an imposed rate: how far they press the grains into each other.
#pragma once

#include <string>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::shear {

// Neighbouring layers of a simple shear (centres up to 2 r_max apart along y) meet at about
// gammadot 2 r_max. An undamped head-on collision of the two heaviest grains at that speed presses
// them by the overlap where the elastic energy of the pair's law (dem normal_elastic_energy) is the
// kinetic energy m* v^2 / 2; `ratio` is that overlap over limits.max_overlap r_max, where a run
// fails. Velocity fluctuations of a sheared flow make collisions faster than the mean speed
// difference: shear2d_dry (linear, kappa 1e4) failed at I = 6, ratio 0.42, and ran at I = 5, ratio 0.35;
// shear3d_frictionless (Hertz) failed at I = 5, ratio 0.94, and ran at I = 3, ratio 0.63.
struct ShearCollision {
  double speed = 0;  // gammadot 2 r_max
  double ratio = 0;  // the undamped overlap at that speed, over limits.max_overlap r_max
};
ShearCollision shear_collision(const Model& m);  // zero where no rate is imposed, or in a paste

// "the imposed shear makes neighbours meet at about gammadot 2 r_max = V, where an undamped
// collision of the heaviest grains presses them by R of limits.max_overlap": the refusal's and the
// failure's words.
std::string collision_text(const Model& m, const ShearCollision& c);
// The imposed rate's `value` scaled to bring `ratio` to `target` (the overlap goes as the speed,
// Hertz's as its 4/5 power).
double rate_for(const Model& m, double value, double ratio, double target);

// The factor by which the contacts' stiffness must grow to bring `ratio` to `target`, as the key of
// that stiffness takes it: k_n (the overlap goes as 1/sqrt(k_n)) times f^2, a Hertz modulus
// (as E^(-2/5)) times f^(5/2), a spring-dashpot's contact time (as t_c) divided by f, f =
// ratio / target. Text such as "k_n 4.2 times larger".
std::string stiffer_by(const Model& m, const std::string& key, double ratio, double target);

// The overlap failure of a grain in a flow sheared at an imposed rate, explained: how hard the
// shear's collisions press (shear_collision) and, in the first unit of strain, that a packing
// sheared from rest presses its contacts before its box can dilate. "" where the shear is not at
// an imposed rate. `key` is the stiffness key to name.
std::string shear_overlap_advice(const Model& m, const State& s, const std::string& key);

}  // namespace silt::shear
