// Velocity Verlet, split around the force stages (Allen & Tildesley 1987, sec. 3.2.1):
//   kick_drift:   v(t + dt/2) = v(t) + dt/2 a(t);   x(t + dt) = x(t) + dt v(t + dt/2)
//   ... forces at (x(t + dt), v(t + dt/2)) ...
//   kick:         v(t + dt) = v(t + dt/2) + dt/2 a(t + dt)
// Angular velocities follow the same kicks (grains are spheres or disks: no orientation is
// needed). Velocity-dependent forces see the half-step velocity, as in LAMMPS fix nve/sphere.
//
// Controlled box lengths (Peyneau 2009 eq. 3.9-3.11) are integrated with the same scheme. With
// reduced coordinates s = L^-1 x and v = L ds/dt (the velocity relative to the affine flow),
// a drift at constant ds/dt is x <- lo + lambda (x - lo + dt v) and v <- lambda v with
// lambda = L(t + dt) / L(t); lambda = 1 when no length moves, and the scheme is plain Verlet.
// The neighbour lists need the displacement relative to that flow (particle_disp) and the
// affine strain (nbr_strain): a pair's separation changes by at most both.
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "core/assert.hpp"
#include "core/owned.hpp"
#include "core/simd_level.hpp"
#include "dem/grain_pass.hpp"
#include "dem/grain_pass_avx2.hpp"
#include "dem/stages.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {
namespace {

using grain_pass::DriftArgs;
using grain_pass::KickArgs;
using grain_pass::kMaxSources;

// The end of a grain's drift, xi its new position: a position gone to NaN or infinity (from a
// non-finite force, or a grain thrown away) stops the run at this step, as a non-finite velocity
// does in the kick; then the position is wrapped into the box.
template <int D>
void finish_position(const DriftArgs<D>& a, int64_t i, double* xi) {
  double xs = 0;
  for (int k = 0; k < D; ++k) xs += xi[k];
  if (!std::isfinite(xs)) a.nonfinite->raise(i, 0);
  a.img.wrap(xi, a.box);
}

// Whether the sum of a grain's velocities (after its kick) is finite.
template <int D>
bool motion_finite(const KickArgs<D>& a, int64_t i) {
  double sum = 0;
  for (int k = 0; k < D; ++k) sum += a.v[D * i + k];
  for (int k = 0; k < kRotDim<D>; ++k) sum += a.w[kRotDim<D> * i + k];
  return std::isfinite(sum);
}

// The whole groups of four grains of [b, e) through a vector kernel, kernel(i, m, redo) for m
// groups from grain i at a time, then fix(g) for each grain g whose bit the kernel set in redo
// (bit l of entry q: grain i + 4 q + l). Returns where the grains left to the scalar loop start.
template <class Kernel, class Fix>
int64_t over_groups(int64_t b, int64_t e, Kernel&& kernel, Fix&& fix) {
  constexpr int64_t kChunk = 256;  // grains per call: their flags fit on the stack
  uint8_t redo[kChunk / 4];
  const int64_t end = b + (e - b) / 4 * 4;
  for (int64_t i = b; i < end; i += kChunk) {
    const int64_t m = std::min(kChunk, end - i) / 4;
    kernel(i, m, redo);
    for (int64_t q = 0; q < m; ++q)
      for (int l = 0; redo[q] >> l; ++l)
        if (redo[q] >> l & 1) fix(i + 4 * q + l);
  }
  return end;
}

// Kick and drift grains [b, e); returns the largest squared displacement since the last build
// and the largest squared displacement of this drift.
// The arguments come by value: a local copy that the stores to the arrays cannot alias, so the
// loop keeps them in registers (captured in a closure they would be reloaded after each store).
template <int D, bool Affine>
std::array<double, 2> drift_scalar(const DriftArgs<D> a, int64_t b, int64_t e) {
  constexpr int R = kRotDim<D>;
  double* __restrict x = a.x;
  double* __restrict v = a.v;
  double* __restrict w = a.w;
  double* __restrict disp = a.disp;
  const double* __restrict f = a.f;
  const double* __restrict t = a.t;
  double worst = 0, worst_step = 0;
  for (int64_t i = b; i < e; ++i) {
    if (a.frozen[i]) continue;
    const double im = a.inv_m[i];
    double xi[3], d2 = 0, s2 = 0;
    const double cy = v[D * i + 1];  // c_y(t), before its kick
    for (int k = 0; k < D; ++k) {
      double vk = v[D * i + k] + a.h * (f[D * i + k] * im + a.g[k]);
      if constexpr (Affine)
        if (k == 0 && a.gd != 0.0) vk -= a.h * a.gd * cy;
      const double step = a.dt * vk;
      if constexpr (Affine) {
        xi[k] = a.lo[k] + a.lambda[k] * (x[D * i + k] - a.lo[k] + step);
        v[D * i + k] = vk * a.lambda[k];
      } else {
        xi[k] = x[D * i + k] + step;
        v[D * i + k] = vk;
      }
      disp[D * i + k] += step;
      d2 += disp[D * i + k] * disp[D * i + k];
      s2 += step * step;
    }
    // Shear flow at the mid-step height (second order).
    if constexpr (Affine) xi[0] += a.dt * a.gd * (x[D * i + 1] + 0.5 * a.dt * v[D * i + 1] - a.lo[1]);
    finish_position(a, i, xi);
    for (int k = 0; k < D; ++k) x[D * i + k] = xi[k];
    const double ii = a.inv_i[i];
    for (int k = 0; k < R; ++k) w[R * i + k] += a.h * t[R * i + k] * ii;
    worst = std::max(worst, d2);
    worst_step = std::max(worst_step, s2);
  }
  return {worst, worst_step};
}

// The same, four grains at a time where the processor has AVX2 (grain_pass_avx2.hpp; the same
// bits), the last ones by the scalar loop.
template <int D, bool Affine>
std::array<double, 2> drift_range(const DriftArgs<D> a, int64_t b, int64_t e) {
#if defined(__SSE4_1__)
  if (avx2_in_use()) {
    double worst[2] = {0, 0};
    const int64_t tail = over_groups(
        b, e, [&](int64_t i, int64_t m, uint8_t* redo) { grain_avx2::drift_grains<D, Affine>(a, i, m, worst, redo); },
        [&](int64_t g) { finish_position(a, g, a.x + D * g); });
    const std::array<double, 2> rest = drift_scalar<D, Affine>(a, tail, e);
    return {std::max(worst[0], rest[0]), std::max(worst[1], rest[1])};
  }
#endif
  return drift_scalar<D, Affine>(a, b, e);
}

// The arguments of a drift after a half kick of `kick` dt/2.
template <int D, bool Affine>
DriftArgs<D> drift_args(const Model& m, State& s, double kick) {
  // The box lengths moved first (shear::box_drift): L(t + dt) / L(t) of each.
  const Vec3a lambda = Affine ? s.box_stretch : Vec3a{1, 1, 1};
  DriftArgs<D> a{s.dt,
                 kick * 0.5 * s.dt,
                 s.shear_rate,
                 &s.events[event::kNonFinite],
                 {},
                 {},
                 {},
                 PeriodicImage<D>(s.box),
                 s.box,
                 s.particle_x.data(),
                 s.particle_v.data(),
                 s.particle_w.data(),
                 s.particle_disp.data(),
                 s.particle_f.data(),
                 s.particle_t.data(),
                 s.particle_inv_m.data(),
                 s.particle_inv_i.data(),
                 s.particle_frozen.data()};
  for (int k = 0; k < D; ++k) {
    a.lo[k] = s.box.lo[k];
    a.g[k] = m.gravity[k];
    a.lambda[k] = lambda[k];
  }
  return a;
}

// The largest displacements of a drift into the neighbour list's scalars.
void store_displacements(State& s, const std::array<double, 2>& max_d2) {
  s.nbr_max_disp = std::sqrt(max_d2[0]);
  s.nbr_step_disp = std::sqrt(max_d2[1]);
}

template <int D, bool Affine>
void kick_drift_dim(const Model& m, State& s, double kick, const Shares& shares, double* cost) {
  const DriftArgs<D> a = drift_args<D, Affine>(m, s, kick);
  store_displacements(
      s, owned_max<2>(s.n, shares, cost, [a](int64_t b, int64_t e) { return drift_range<D, Affine>(a, b, e); }));
}

// The force sources into particle_f / particle_t (contact_forces left the pair sums there;
// without friction it wrote no torque: Torque false starts from zero) and, with Kick, the second
// half kick of grains [b, e). Arguments by value, as in drift_range.
template <int D, bool Kick, bool Torque, bool Sources>
void kick_scalar(const KickArgs<D> a, int64_t b, int64_t e) {
  constexpr int R = kRotDim<D>;
  double* __restrict force = a.force;
  double* __restrict torq = a.torq;
  double* __restrict v = a.v;
  double* __restrict w = a.w;
  for (int64_t i = b; i < e; ++i) {
    double f[D];
    for (int k = 0; k < D; ++k) f[k] = force[D * i + k];
    if constexpr (!Torque)
      for (int k = 0; k < R; ++k) torq[R * i + k] = 0;
    if constexpr (Sources) {
      for (int src = 0; src < a.n_force; ++src) {
        const int items = a.force_items[src];
        const double* p = a.force_src[src] + D * i * items;
        for (int q = 0; q < items; ++q)
          for (int k = 0; k < D; ++k) f[k] += p[D * q + k];
      }
      for (int src = 0; src < a.n_torque; ++src)
        for (int k = 0; k < R; ++k) torq[R * i + k] += a.torque_src[src][R * i + k];
      if (a.n_force > 0)
        for (int k = 0; k < D; ++k) force[D * i + k] = f[k];
    }
    if constexpr (Kick) {
      if (a.frozen[i]) continue;
      const double im = a.inv_m[i], ii = a.inv_i[i];
      for (int k = 0; k < D; ++k) v[D * i + k] += a.h * (f[k] * im + a.g[k]);
      if (a.gd != 0.0) v[D * i] -= a.h * a.gd * v[D * i + 1];  // with c_y(t + dt)
      for (int k = 0; k < R; ++k) w[R * i + k] += a.h * torq[R * i + k] * ii;
      // A NaN or Inf anywhere in the grain's motion reaches its velocities.
      if (!motion_finite(a, i)) a.nonfinite->raise(i, 0);
    }
  }
}

// The same, four grains at a time where the processor has AVX2 and there are no other force
// sources (grain_pass_avx2.hpp; the same bits), the last ones by the scalar loop.
template <int D, bool Kick, bool Torque, bool Sources>
void kick_range(const KickArgs<D> a, int64_t b, int64_t e) {
#if defined(__SSE4_1__)
  if constexpr (Kick && !Sources) {
    if (avx2_in_use()) {
      if constexpr (!Torque) std::fill(a.torq + kRotDim<D> * b, a.torq + kRotDim<D> * e, 0.0);
      const int64_t tail = over_groups(
          b, e,
          [&](int64_t i, int64_t m, uint8_t* redo) {
            a.gd != 0.0 ? grain_avx2::kick_grains<D, true>(a, i, m, redo)
                        : grain_avx2::kick_grains<D, false>(a, i, m, redo);
          },
          [&](int64_t g) {
            if (!a.frozen[g] && !motion_finite(a, g)) a.nonfinite->raise(g, 0);
          });
      return kick_scalar<D, Kick, true, Sources>(a, tail, e);
    }
  }
#endif
  kick_scalar<D, Kick, Torque, Sources>(a, b, e);
}

// The arguments of a kick of h (0 for the sum alone) with the force sources.
template <int D>
KickArgs<D> kick_args(const Model& m, State& s, const ForceSources& sources, double h) {
  KickArgs<D> a{h,
                m.shear.on ? s.shear_rate : 0.0,
                {},
                0,
                0,
                {},
                {},
                {},
                s.particle_inv_m.data(),
                s.particle_inv_i.data(),
                s.particle_frozen.data(),
                s.particle_f.data(),
                s.particle_t.data(),
                s.particle_v.data(),
                s.particle_w.data(),
                &s.events[event::kNonFinite]};
  for (int k = 0; k < D; ++k) a.g[k] = m.gravity[k];
  SILT_ASSERT(sources.size() <= static_cast<size_t>(kMaxSources), "too many force sources");
  for (const ForceSource& src : sources) {
    const Extent e = field_info(src.force).extent;
    SILT_ASSERT(e == Extent::kGrainVec || e == Extent::kGrainWallVec,
                "a force source is per grain or per grain and wall");
    a.force_items[a.n_force] = e == Extent::kGrainWallVec ? s.n_walls : 1;
    a.force_src[a.n_force++] = double_field(s, src.force).data();
    if (src.torque != kNoField) a.torque_src[a.n_torque++] = double_field(s, src.torque).data();
  }
  return a;
}

// body(torque, with_sources) with both as std::integral_constant: contact_forces writes no torque
// without friction (the sum then starts from zero); without sources (no walls, no module's
// force) the sum has nothing to add.
template <class Body>
void with_kick_flags(const Model& m, const ForceSources& sources, Body&& body) {
  const bool any = !sources.empty();
  if (m.pair_friction()) any ? body(std::true_type{}, std::true_type{}) : body(std::true_type{}, std::false_type{});
  else any ? body(std::false_type{}, std::true_type{}) : body(std::false_type{}, std::false_type{});
}

template <int D, bool Kick>
void kick_dim(const Model& m, State& s, const ForceSources& sources, const Shares& shares, double* cost) {
  const KickArgs<D> a = kick_args<D>(m, s, sources, 0.5 * s.dt);
  with_kick_flags(m, sources, [&](auto torque, auto with_sources) {
    owned_for(s.n, shares, cost, [a](int64_t b, int64_t e) {
      kick_range<D, Kick, decltype(torque)::value, decltype(with_sources)::value>(a, b, e);
    });
  });
}

// The kick of grains [b, e) with k, its non-finite motions raised in `slot`, the block's own (the
// caller reports them and leaves the block unmoved: its step fails). Returns the kick's arguments.
template <int D, bool Torque, bool Sources>
KickArgs<D> kick_block(KickArgs<D> k, EventSlot& slot, int64_t b, int64_t e) {
  k.nonfinite = &slot;
  kick_range<D, true, Torque, Sources>(k, b, e);
  return k;
}

// The second half kick of the last step (half step h_last) and this step's kick and drift, block
// by block: each block of grains is kicked twice and moved while it is in the cache. A block whose
// late kick meets a non-finite motion raises non_finite_late with the lowest grain id (ids, not
// indices: update_neighbors may renumber the grains before the step is diagnosed) and is not
// moved (the step fails; its positions stay finite for the neighbour search).
template <int D>
void late_kick_drift_dim(const Model& m, State& s, const ForceSources& sources, double h_last, const Shares& shares,
                         double* cost) {
  const KickArgs<D> k = kick_args<D>(m, s, sources, h_last);
  const DriftArgs<D> a = drift_args<D, false>(m, s, 1.0);
  EventSlot* late = &s.events[event::kNonFiniteLate];
  const int32_t* id = s.particle_id.data();
  with_kick_flags(m, sources, [&](auto torque, auto with_sources) {
    store_displacements(s, owned_max<2>(s.n, shares, cost, [k, a, late, id](int64_t b, int64_t e) {
                          EventSlot bad;
                          const KickArgs<D> kb =
                              kick_block<D, decltype(torque)::value, decltype(with_sources)::value>(k, bad, b, e);
                          if (!bad.raised()) return drift_range<D, false>(a, b, e);
                          int32_t lowest = id[bad.first()];
                          for (int64_t i = b; i < e; ++i)
                            if (!a.frozen[i] && !motion_finite(kb, i)) lowest = std::min(lowest, id[i]);
                          late->raise(lowest, 0);  // not moved: the step fails
                          return std::array<double, 2>{0, 0};
                        }));
  });
}

// The drift after a half kick of `kick` dt/2 (1: velocity Verlet; 0: the drift alone).
void kick_then_drift(const Model& m, State& s, double kick, const Shares& shares, double* cost) {
  const bool affine = m.deforming_box();
  if (m.dim == 2)
    affine ? kick_drift_dim<2, true>(m, s, kick, shares, cost) : kick_drift_dim<2, false>(m, s, kick, shares, cost);
  else affine ? kick_drift_dim<3, true>(m, s, kick, shares, cost) : kick_drift_dim<3, false>(m, s, kick, shares, cost);
}

// kick_and_next_drift for D and the torque flag of kick_dim.
template <int D, bool Torque>
GrainBlockPass kick_and_next_drift_dim(const Model& m, State& s, EventSlot* drift_events) {
  const KickArgs<D> k = kick_args<D>(m, s, {}, 0.5 * s.dt);
  DriftArgs<D> a = drift_args<D, false>(m, s, 1.0);
  a.nonfinite = drift_events;
  return [k, a](int64_t b, int64_t e) {
    EventSlot bad;
    kick_block<D, Torque, false>(k, bad, b, e);
    if (!bad.raised()) return drift_range<D, false>(a, b, e);
    k.nonfinite->raise(bad.first(), 0);  // this step's failure: its grains are not moved
    return std::array<double, 2>{0, 0};
  };
}

}  // namespace

void kick_drift(const Model& m, State& s, const Shares& shares, double* cost) {
  kick_then_drift(m, s, 1.0, shares, cost);
}

void drift(const Model& m, State& s) { kick_then_drift(m, s, 0.0, Shares{}, nullptr); }

void kick(const Model& m, State& s, const ForceSources& sources, const Shares& shares, double* cost) {
  if (m.dim == 2) kick_dim<2, true>(m, s, sources, shares, cost);
  else kick_dim<3, true>(m, s, sources, shares, cost);
}

void late_kick_drift(const Model& m, State& s, const ForceSources& sources, double h_last, const Shares& shares,
                     double* cost) {
  SILT_ASSERT(!m.deforming_box() && !m.shear.on, "a kick is left to the next step only in a fixed box");
  if (m.dim == 2) late_kick_drift_dim<2>(m, s, sources, h_last, shares, cost);
  else late_kick_drift_dim<3>(m, s, sources, h_last, shares, cost);
}

GrainBlockPass kick_and_next_drift(const Model& m, State& s, EventSlot* drift_events) {
  SILT_ASSERT(!m.deforming_box() && !m.shear.on, "the next step's drift runs early only in a fixed box");
  GrainBlockPass out;
  with_kick_flags(m, {}, [&](auto torque, auto) {
    out = m.dim == 2 ? kick_and_next_drift_dim<2, decltype(torque)::value>(m, s, drift_events)
                     : kick_and_next_drift_dim<3, decltype(torque)::value>(m, s, drift_events);
  });
  return out;
}

void sum_forces(const Model& m, State& s, const ForceSources& sources) {
  if (m.dim == 2) kick_dim<2, false>(m, s, sources, Shares{}, nullptr);
  else kick_dim<3, false>(m, s, sources, Shares{}, nullptr);
}

void keep_springs(const State& s, DemWorkspace& w) {
  w.kept_pair_hist.assign(s.pair_hist.begin(), s.pair_hist.end());
  w.kept_wall_hist.assign(s.wall_hist.begin(), s.wall_hist.end());
}

void restore_springs(State& s, const DemWorkspace& w) {
  SILT_ASSERT(w.kept_pair_hist.size() == s.pair_hist.size() && w.kept_wall_hist.size() == s.wall_hist.size(),
              "the springs were kept for another pair list");
  std::copy(w.kept_pair_hist.begin(), w.kept_pair_hist.end(), s.pair_hist.begin());
  std::copy(w.kept_wall_hist.begin(), w.kept_wall_hist.end(), s.wall_hist.begin());
}

}  // namespace silt::dem
