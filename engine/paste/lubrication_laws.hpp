// The lubrication resistances between two grains at gap h, Peyneau (2009) sec. 1.5.2: pure
// functions of the gap, the equivalent radius R_eq (2 / R_eq = 1 / R_i + 1 / R_j: R for two grains
// of radius R; dem::reduced_radius) and the law. With it xi_N = 6 pi eta (R_i R_j / (R_i + R_j))^2 / h,
// the leading term of the exact two-sphere resistance (Jeffrey & Onishi 1984).
//
// Smooth spheres (eq. 1.26, 1.27):  xi_N = (3/2) pi eta R_eq^2 / h,  xi_T = pi eta R_eq ln(2 R_eq / h),
// forces F_N = -xi_N V_N and F_T = -xi_T V_T (resisting the relative velocity; the thesis's sign
// in the middle of eq. 1.27 is a typo). Roughness as a cutoff h_min (eq. 1.28, 1.29): below it
// the laws follow their tangents at h_min (linear cutoff: continuous and C1 at h_min) down to
// contact, and stay constant in contact (h < 0), so a quasi-contact becoming a contact changes
// no sparsity pattern; above h_max there is no connection. The "constant" cutoff of Table 2.3
// holds the value at h_min from h_min down (the thesis does not write it; the value at h_min is
// the natural reading). The thesis applies these sphere formulas to 2D disks unchanged, and so
// does silt. The tangential law is the leading term for h << R_eq: it falls to 0 at h = 2 R_eq
// and changes sign beyond, which h_max = a/2 exceeds for every pair smaller than two grains of
// diameter a (the thesis does not say what it did there). silt holds it at its value at h = R_eq,
// pi eta R_eq ln 2, for larger gaps: positive (a gap with no tangential resistance would let a
// grain slide along it for free, making Xi singular), continuous, and unchanged below R_eq. A
// cutoff h_min beyond R_eq (h_min/a up to 0.5 is allowed, R_eq of two small grains is below) meets
// the law where it is held: the linear cutoff's tangent is flat, xi_T = pi eta R_eq ln 2 down to
// contact (the tangent of ln(2 R_eq / h) went negative beyond h_min = 2 R_eq).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace silt::paste {

enum class Cutoff { kLinear, kConstant };

struct LubricationLaw {
  double eta = 1;    // liquid viscosity [Pa s]
  double h_min = 0;  // roughness cutoff [m]
  double h_max = 0;  // connection range [m]
  Cutoff cutoff = Cutoff::kLinear;
};

// Eq. 1.28: the normal resistance [N s/m]; 0 beyond h_max.
inline double xi_normal(double h, double r_eq, const LubricationLaw& law) {
  if (h > law.h_max) return 0;
  const double c = 1.5 * std::numbers::pi * law.eta * r_eq * r_eq;
  if (h >= law.h_min) return c / h;
  if (law.cutoff == Cutoff::kConstant) return c / law.h_min;
  const double hc = std::max(h, 0.0);  // constant in contact
  return c * (2 / law.h_min - hc / (law.h_min * law.h_min));
}

// Eq. 1.29: the tangential resistance [N s/m]; 0 beyond h_max.
inline double xi_tangential(double h, double r_eq, const LubricationLaw& law) {
  if (h > law.h_max) return 0;
  const double c = std::numbers::pi * law.eta * r_eq;
  if (h >= law.h_min) return c * std::log(2 * r_eq / std::min(h, r_eq));
  if (law.cutoff == Cutoff::kConstant) return c * std::log(2 * r_eq / std::min(law.h_min, r_eq));
  // At an h_min beyond R_eq the law is held flat there, and so is its tangent.
  if (law.h_min >= r_eq) return c * std::numbers::ln2;
  const double hc = std::max(h, 0.0);
  return c * (1 + std::log(2 * r_eq / law.h_min) - hc / law.h_min);
}

}  // namespace silt::paste
