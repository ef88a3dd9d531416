// How the paste's solve scales its unknowns (lubrication_solve): shared by the solve and the
// stress's accuracy check, which read the solution in the solve's units.
#pragma once
#include <cmath>
#include <cstdint>

#include "paste/system.hpp"

namespace silt::paste {

// The unknowns' units, as the solve sees them: Xi's translation entries grow as eta a and its
// rotation and box entries as eta a^3 (a torque or a virial over an angular velocity or a strain
// rate), so a residual norm and the step's change criterion weigh equations of different units
// alike, and the paste depended on its unit of length (2D disks of 1e-4 m under 100 N/m took 3 CG
// iterations where the same grains in units of a took 2, and the run parted from theirs at the
// fourth step). Each rotation and box strain rate is solved for times ell (a velocity: ell omega
// is the speed of a grain's surface) and its equation divided by ell (a force): ell is the largest
// radius a / 2 rounded to a power of two, exact in floating point (and 1 for spheres of radius 1,
// whose bits it leaves as they were), so that grains scaled by a power of two take the same steps
// to the bit.
struct UnknownScale {
  double inv_ell = 1;  // 1 / ell
  int64_t translations_end = 0;
  int per_grain = 1, dim = 2;
  bool identity() const { return inv_ell == 1; }
  // The factor s_k of unknown k: the system solved is S Xi S (S^-1 V) = S F.
  double of(int64_t k) const { return k >= translations_end || k % per_grain >= dim ? inv_ell : 1.0; }
};

inline UnknownScale unknown_scale(const SystemLayout& L, double a) {
  UnknownScale u;
  u.inv_ell = 1 / std::exp2(std::round(std::log2(a / 2)));
  u.translations_end = L.grains * L.per_grain;
  u.per_grain = L.per_grain;
  u.dim = L.dim;
  return u;
}

}  // namespace silt::paste
