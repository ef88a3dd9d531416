// The fluid's grid: a uniform Cartesian grid of cells over the domain, with the velocity
// components on the faces (a staggered "MAC" grid, Harlow & Welch 1965; Izard 2014 sec. 2.2.1)
// and the pressure at the cell centres.
//
// Layout (x fastest): cell (i, j, k) is i + n0 (j + n1 k), with n2 = 1 in 2D. The faces normal to
// axis a have n[a] + 1 entries along a: the x faces (i, j, k), i = 0 .. n0, are at x = lo + i h,
// index i + (n0 + 1)(j + n1 k); the y and z faces likewise. Along a periodic axis the last face
// is the first one again (both are stored, and kept equal).
//
// Boundaries are given per face of the box (Bc). Each decides the condition of the velocity
// (wall: the normal component zero, the tangential ones zero or given or free; inflow: a given
// velocity; outflow: zero normal gradient) and of the pressure's projection step (walls and
// inflow: Neumann, dp/dn = 0; outflow: Dirichlet, p = 0 on the face; periodic: periodic).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace silt::fluid {

enum class BcType : uint8_t {
  kPeriodic,
  kNoSlip,    // a wall; its tangential velocity is Bc::velocity (0, or a moving lid)
  kFreeSlip,  // a wall without friction: zero tangential stress
  kInflow,    // the velocity Bc::velocity on the face (a plug, or a parabola: Bc::parabolic)
  kOutflow,   // zero normal gradient of the velocity, p = 0 on the face
};
inline const char* bc_name(BcType t) {
  switch (t) {
    case BcType::kPeriodic: return "periodic";
    case BcType::kNoSlip: return "no_slip";
    case BcType::kFreeSlip: return "free_slip";
    case BcType::kInflow: return "inflow";
    case BcType::kOutflow: return "outflow";
  }
  return "?";
}

struct Bc {
  BcType type = BcType::kPeriodic;
  std::array<double, 3> velocity{0, 0, 0};  // kNoSlip: the wall's (tangential) velocity; kInflow: the inflow's
  bool parabolic = false;  // kInflow: Bc::velocity is the peak of a profile vanishing on the other walls
};

// The pressure's condition on a face of the box, from the velocity's.
enum class PressureBc : uint8_t { kPeriodic, kNeumann, kDirichlet };
inline PressureBc pressure_bc(BcType t) {
  switch (t) {
    case BcType::kPeriodic: return PressureBc::kPeriodic;
    case BcType::kOutflow: return PressureBc::kDirichlet;
    default: return PressureBc::kNeumann;
  }
}

struct Grid {
  int dim = 2;
  std::array<int64_t, 3> n{1, 1, 1};  // cells per axis (n[2] = 1 in 2D)
  std::array<double, 3> lo{0, 0, 0};
  std::array<double, 3> h{1, 1, 1};       // spacing per axis [m]
  std::array<std::array<Bc, 2>, 3> bc{};  // [axis][0: low face, 1: high face]

  int64_t cells() const { return n[0] * n[1] * n[2]; }
  // Entries of the array of the faces normal to axis a.
  int64_t faces(int a) const {
    if (a >= dim) return 0;
    std::array<int64_t, 3> m = n;
    ++m[a];
    return m[0] * m[1] * m[2];
  }
  // Points along each axis of the faces normal to a (n + 1 along a).
  std::array<int64_t, 3> face_dims(int a) const {
    std::array<int64_t, 3> m = n;
    ++m[a];
    return m;
  }
  bool periodic(int a) const { return bc[a][0].type == BcType::kPeriodic; }
  int64_t cell(int64_t i, int64_t j, int64_t k = 0) const { return i + n[0] * (j + n[1] * k); }
  PressureBc pbc(int a, int side) const { return pressure_bc(bc[a][side].type); }
  double cell_volume() const { return h[0] * h[1] * (dim == 3 ? h[2] : 1.0); }
  double h_min() const {  // the smallest spacing
    double m = h[0];
    for (int a = 1; a < dim; ++a) m = std::min(m, h[a]);
    return m;
  }
  // Whether a flow whose velocities over the spacing reach `rate` [1/s] has squares over the cells
  // beyond double precision: the sums of (|u| / h)^2 and |u|^2 over the cells, or the kinetic
  // energy and enstrophy they give over the cells' volume (a domain of 1e110 m gave inf), would
  // be inf.
  bool squares_overflow(double rate, double density) const {
    double h_max = h[0];
    for (int a = 1; a < dim; ++a) h_max = std::max(h_max, h[a]);
    const double nc = static_cast<double>(cells()), speed = rate * h_max;
    return !std::isfinite(rate * rate * nc) || !std::isfinite(rate * rate * nc * cell_volume()) ||
           !std::isfinite(speed * speed * nc) || !std::isfinite(0.5 * density * speed * speed * nc * cell_volume());
  }
  // sum_a 1 / h_a^2: the explicit viscous number is nu dt times it.
  double inv_h2_sum() const {
    double inv = 0;
    for (int a = 0; a < dim; ++a) inv += 1 / (h[a] * h[a]);
    return inv;
  }
};

}  // namespace silt::fluid
