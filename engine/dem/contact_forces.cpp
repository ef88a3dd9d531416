// Grain-grain contact forces over the Verlet list.
//
// For a listed pair (i, j) with d = x_i - x_j (nearest image), n = d/|d| points from j to i and
// the overlap is r_i + r_j - |d|. The relative velocity of i with respect to j at the contact
// point is
//   v_rel = v_i - v_j + G d - (r_i w_i + r_j w_j) x n,
// where G d is the difference of the affine box flow between the two centres (G = diag(dL/dt /
// L) under stress control, plus the shear rate at (x, y) under Lees-Edwards shear; zero
// otherwise). The force on i is F = F_n n + F_t (F_t from the tangential spring); j receives
// -F. The torque on i is (-r_i n) x F_t = -r_i (n x F_t), on j (r_j n) x (-F_t) = -r_j (n x F_t).
// Pairs that no longer touch drop their tangential history (LAMMPS gran/*/history) and their
// force; pair_touch says which pairs may hold either, so that only those are cleared.
// Both grains receive the pair's force and torque at once, in the order of the pair schedule
// (pair_schedule.hpp), which makes the sums independent of the number of threads; the force on
// i is also kept per pair (pair_f) for the stress and the contact network, in the steps whose
// end is seen (State::boundary_seen).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "core/assert.hpp"
#include "core/parallel.hpp"
#include "core/simd_level.hpp"
#include "core/small_vec.hpp"
#include "dem/contact_candidates.hpp"
#include "dem/contact_laws.hpp"
#include "dem/pair_schedule.hpp"
#include "dem/stages.hpp"
#include "dem/touch_pass.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {
namespace {

// Values per touching pair that the tangential pass leaves for the sums, together: force on i,
// updated spring, moment n x F_t.
template <int D>
constexpr int kOut = 2 * D + kRotDim<D>;
// The records go in groups of kLanes pairs, field by field within a group (value k of pair q at
// out[kOut * (q - q % kLanes) + k * kLanes + q % kLanes]): the tangential pass stores each field
// of kLanes pairs with one instruction.
constexpr int64_t kLanes = 4;
template <int D>
inline int64_t record(int64_t q) {
  return kOut<D> * (q & ~(kLanes - 1)) + (q & (kLanes - 1));
}

// Scratch of one task: the touching pairs of its rows, their grains and separations, found by
// the first passes, columns (one array per quantity, so that the loop over them vectorizes)
// that the normal pass fills for the tangential one, and the records (kOut per pair) that the
// tangential pass leaves for the sums.
template <int D>
struct Touching {
  enum Column { kN = 0, kVt = D, kXi = 2 * D, kFn = 3 * D, kK, kMeff, kMu, kColumns };
  std::vector<int32_t> pair;
  std::vector<int32_t> gi, gj;  // the grains of each touching pair
  std::vector<double> d;        // separation (nearest image), |d|, 1 / |d|: column k from d[k * cap]
  std::vector<double> columns;
  std::vector<double> out;  // kOut<D> per entry, laid out by record<D>
  size_t cap = 0;
  void reserve(size_t n) {
    n = (n + kLanes - 1) / kLanes * kLanes;  // whole groups: the tangential pass reads them
    if (cap < n) {
      cap = n;
      pair.resize(n);
      gi.resize(n);
      gj.resize(n);
      d.resize((D + 2) * n);
      columns.resize(kColumns * n);
      out.resize(kOut<D> * n);
    }
  }
  double* col(int k) { return columns.data() + k * cap; }
};

// The tangential springs of the touching pairs, column by column (tangential_spring of
// contact_laws.hpp): the loop has neither indirection nor branch, and vectorizes. In: unit
// normals n, tangential velocities vt, normal forces fn, normal stiffnesses kn, reduced masses m;
// springs xi. Out, one record of kOut values per pair (pass 3 reads them together; record<D>):
// the pair force f = fn n + F_t, the updated spring, and the moment n x F_t. Dashpot: zeta_t > 0.
// PairMu: the friction coefficient of each pair in mu (pairs of different materials), else
// `friction` for all.
template <int D, bool Dashpot, bool PairMu>
[[gnu::always_inline]] inline void tangential_columns(int64_t c, double dt, double kt_ratio, double friction,
                                                      const double* mu, double zeta_t, double* const* n,
                                                      double* const* vt, const double* fn, const double* kn,
                                                      const double* m, double* const* xi, double* __restrict out) {
  // Whole groups of kLanes: the last one may run on values past c, which are ignored.
  for (int64_t b = 0; b < c; b += kLanes) {
    double* __restrict ob = out + kOut<D> * b;
    SILT_IVDEP
    for (int64_t l = 0; l < kLanes; ++l) {
      const int64_t q = b + l;
      const double kt = kt_ratio * kn[q];
      SVec<D> s, nq, vq, ft;
      for (int k = 0; k < D; ++k) {
        s[k] = xi[k][q];
        nq[k] = n[k][q];
        vq[k] = vt[k][q];
      }
      const double ct = Dashpot ? tangential_dashpot(zeta_t, m[q], kt) : 0.0;
      const double mu_q = PairMu ? mu[q] : friction;
      tangential_spring<D, Dashpot>(s.c, nq.c, vq.c, dt, kt, mu_q * std::abs(fn[q]), ct, ft.c);
      double* o = ob + l;
      for (int k = 0; k < D; ++k) {
        o[k * kLanes] = fn[q] * nq[k] + ft[k];
        o[(D + k) * kLanes] = s[k];
      }
      const SOmega<D> mt = moment(nq, ft);
      if constexpr (D == 3)
        for (int k = 0; k < 3; ++k) o[(2 * D + k) * kLanes] = mt[k];
      else o[2 * D * kLanes] = mt;
    }
  }
}

// On processors with AVX2 the loop runs four pairs per instruction instead of two: the same
// IEEE operations on each pair, so the same bits (core/simd_level.hpp). AVX-512 gains nothing
// here (3,000 steps of the settled chute on one thread: 1.63 to 1.84 s either way), so the loop
// stays at AVX2, which no processor slows its clock for.
template <int D, bool Dashpot, bool PairMu>
void tangential_pass(int64_t c, double dt, double kt_ratio, double friction, const double* mu, double zeta_t,
                     double* const* n, double* const* vt, const double* fn, const double* kn, const double* m,
                     double* const* xi, double* __restrict out) {
  run_simd<SimdLevel::kAvx2>([&] {
    tangential_columns<D, Dashpot, PairMu>(c, dt, kt_ratio, friction, mu, zeta_t, n, vt, fn, kn, m, xi, out);
  });
}

template <int D>
struct PairArgs {
  ContactParams cp;
  PeriodicImage<D> img;
  double dt, max_overlap, shear_rate;
  double fn_floor;  // 0 when attractive normal forces are clipped, -inf otherwise
  SVec<D> grad;     // affine velocity gradient: stretching rates on the diagonal
  int64_t n;
  const double* x;
  const double* v;
  const double* w;
  const double* r;
  const double* im;
  const int32_t* start;
  const int32_t* pi;
  const int32_t* pj;
  const int32_t* cand_end;  // contact candidates (contact_candidates.hpp)
  const int32_t* cand_p;
  const int32_t* cand_i;
  const int32_t* cand_j;
  double* pf;
  double* hist;
  uint8_t* touch;
  double* force;
  double* torque;
  EventSlot* overlap_alarm;
  bool keep_pf;  // store the pair forces (State::boundary_seen)
  // Materials: the law of each pair of groups, [g_i * n_groups + g_j] (Model::pair_contact).
  const ContactParams* table;
  const int32_t* group;
  int64_t n_groups;
};

// The pairs of one block of rows, in two passes. The first tests every listed pair and packs
// the touching ones without a branch, clearing the force and the history of pairs that have just
// come apart; the second computes the laws for the packed list. In a flowing bed most listed
// pairs do not touch, in no predictable pattern: one loop with an `if` mispredicts on most pairs
// and stalls the pipeline. Pairs that were already apart are not written at all (the list is
// mostly those). The arguments come by value: a local copy that the stores to the arrays cannot
// alias, so the loops keep them in registers.
template <int D, bool Hertz, bool Friction, bool Affine, bool Mat>
void pair_block(const PairArgs<D> a, int64_t blk) {
  using V = SVec<D>;
  const double* __restrict x = a.x;
  const double* __restrict v = a.v;
  const double* __restrict w = a.w;
  const double* __restrict r = a.r;
  const double* __restrict im = a.im;
  const int32_t* __restrict pi = a.pi;
  const int32_t* __restrict pj = a.pj;
  double* __restrict pf = a.pf;
  double* __restrict hist = a.hist;
  double* __restrict force = a.force;
  double* __restrict torque = a.torque;
  const int64_t q0 = a.start[blk * PairSchedule::kBlock], q1 = a.cand_end[blk];
  thread_local Touching<D> tl;
  tl.reserve(static_cast<size_t>(q1 - q0));
  int32_t* __restrict tp = tl.pair.data();
  double* td[D + 2];
  for (int k = 0; k < D + 2; ++k) td[k] = tl.d.data() + k * tl.cap;
  // Pass 1: which candidate pairs touch, in one flat loop over the candidates of the block's
  // rows (a loop per row would mispredict its exit on rows of varying length).
  const int64_t c = touch_pass<D>({x, r, a.cand_p, a.cand_i, a.cand_j, a.touch, pf, Friction ? hist : nullptr}, a.img,
                                  q0, q1, tp, td);
  // Pass 2, the normal law, and pass 3, the tangential spring and the sums on both grains, on
  // the touching pairs in row order. Each pass is a short chain of dependent operations per
  // pair (a square root and a division in each), so the processor overlaps many pairs; as one
  // loop, the chain would be twice as long and fewer pairs would be in flight.
  using T = Touching<D>;
  constexpr int R = kRotDim<D>;
  double* cn[D];
  double* cvt[D];
  double* cxi[D];
  for (int k = 0; k < D; ++k) {
    cn[k] = tl.col(T::kN + k);
    cvt[k] = tl.col(T::kVt + k);
    cxi[k] = tl.col(T::kXi + k);
  }
  double* __restrict out = tl.out.data();
  double* __restrict cfn = tl.col(T::kFn);
  double* __restrict ck = tl.col(T::kK);
  double* __restrict cm = tl.col(T::kMeff);
  double* __restrict cmu = tl.col(T::kMu);
  int32_t* __restrict gi = tl.gi.data();
  int32_t* __restrict gj = tl.gj.data();
  for (int64_t q = 0; q < c; ++q) {
    const int64_t p = tp[q], i = pi[p], j = pj[p];
    // The springs, indexed by pair, are scattered over a large array: ask for those of a later
    // pair now (its load here, and its store in the sums, would otherwise wait on memory).
    if constexpr (Friction) __builtin_prefetch(hist + D * tp[std::min(q + 16, c - 1)], 1);
    gi[q] = static_cast<int32_t>(i);
    gj[q] = static_cast<int32_t>(j);
    V d;
    for (int k = 0; k < D; ++k) d[k] = td[k][q];
    const double ri = r[i], rj = r[j];
    const double dist = td[D][q];
    const V nrm = d * td[D + 1][q];
    const double overlap = ri + rj - dist;
    if (overlap > a.max_overlap * std::min(ri, rj)) a.overlap_alarm->raise(i, overlap / std::min(ri, rj));
    V vr = V::load(v + D * i) - V::load(v + D * j);
    if constexpr (Affine) {
      for (int k = 0; k < D; ++k) vr[k] += a.grad[k] * d[k];
      vr[0] += a.shear_rate * d[1];
    }
    const double vn = vr.dot(nrm);
    const double m_eff = 1.0 / (im[i] + im[j]);
    const ContactParams& cp = Mat ? a.table[a.group[i] * a.n_groups + a.group[j]] : a.cp;
    NormalForce nf = normal_law<Hertz>(cp, m_eff, Hertz ? reduced_radius(ri, rj) : 0.0, overlap, -vn);
    // Without a branch: the sign of F_n varies from contact to contact in no predictable order.
    nf.fn = std::max(nf.fn, a.fn_floor);
    for (int k = 0; k < D; ++k) cn[k][q] = nrm[k];
    cfn[q] = nf.fn;
    if constexpr (Friction) {
      const SOmega<D> wsum = ri * somega_load<D>(w, i) + rj * somega_load<D>(w, j);
      const V vt = vr - vn * nrm - cross_w(wsum, nrm);
      for (int k = 0; k < D; ++k) {
        cvt[k][q] = vt[k];
        cxi[k][q] = hist[D * p + k];
      }
      ck[q] = nf.k;
      cm[q] = m_eff;
      if constexpr (Mat) cmu[q] = cp.friction;
    }
  }
  if constexpr (Friction) {
    if (a.cp.zeta_t > 0)
      tangential_pass<D, true, Mat>(c, a.dt, a.cp.kt_ratio, a.cp.friction, cmu, a.cp.zeta_t, cn, cvt, cfn, ck, cm, cxi,
                                    out);
    else
      tangential_pass<D, false, Mat>(c, a.dt, a.cp.kt_ratio, a.cp.friction, cmu, 0.0, cn, cvt, cfn, ck, cm, cxi, out);
  } else {
    for (int64_t q = 0; q < c; ++q)
      for (int k = 0; k < D; ++k) out[record<D>(q) + k * kLanes] = cfn[q] * cn[k][q];
  }
  auto sums = [&](auto keep_pf) {
    for (int64_t q = 0; q < c; ++q) {
      const int64_t p = tp[q], i = gi[q], j = gj[q];
      const double* o = out + record<D>(q);
      for (int k = 0; k < D; ++k) {
        const double f = o[k * kLanes];
        if constexpr (keep_pf) pf[D * p + k] = f;
        force[D * i + k] += f;
        force[D * j + k] -= f;
      }
      if constexpr (Friction) {
        const double ri = -r[i], rj = -r[j];
        for (int k = 0; k < D; ++k) hist[D * p + k] = o[(D + k) * kLanes];
        for (int k = 0; k < R; ++k) {
          torque[R * i + k] += ri * o[(2 * D + k) * kLanes];
          torque[R * j + k] += rj * o[(2 * D + k) * kLanes];
        }
      }
    }
  };
  if (a.keep_pf) sums(std::true_type{});
  else sums(std::false_type{});
}

template <int D, bool Hertz, bool Friction, bool Affine, bool Mat>
void pair_forces(const Model& m, State& s, DemWorkspace& sc, const GrainBlockPass* then) {
  constexpr int R = kRotDim<D>;
  if (!sc.schedule_valid) sc.new_schedule(s.n, s.nbr_start, s.pair_j);
  // Chosen before, by update_neighbors or select_candidates: a choice here would clear springs
  // after a caller kept them, and one call would differ from the next on the same state.
  SILT_ASSERT(sc.candidates_valid, "contact_forces needs the contact candidates of its pair list");
  PairArgs<D> a{m.contact, PeriodicImage<D>(s.box), s.dt, m.limits.max_overlap, s.shear_rate,
                m.contact.clip_attractive ? 0.0 : -std::numeric_limits<double>::infinity(), SVec<D>::Zero(), s.n,
                s.particle_x.data(), s.particle_v.data(), s.particle_w.data(), s.particle_r.data(),
                s.particle_inv_m.data(), s.nbr_start.data(), s.pair_i.data(), s.pair_j.data(), sc.cand_end.data(),
                sc.cand_p.data(), sc.cand_i.data(), sc.cand_j.data(), s.pair_f.data(), s.pair_hist.data(),
                s.pair_touch.data(), s.particle_f.data(), s.particle_t.data(), &s.events[event::kOverlap],
                // A stage may read them at the end of every step (a controlled box).
                s.boundary_seen || m.pair_forces_every_step, m.pair_contact.data(), s.particle_group.data(),
                static_cast<int64_t>(m.materials.size())};
  if constexpr (Affine)
    for (int k = 0; k < D; ++k) a.grad[k] = s.box_rate[k] / s.box.len[k];
  PairSchedule& sched = sc.schedule;
  auto block = [&a, &sched](int32_t blk) {
    // The first block to write a grain clears its sums.
    constexpr int64_t B = PairSchedule::kBlock;
    for (int32_t k = sched.clears_start[blk]; k < sched.clears_start[blk + 1]; ++k) {
      const int64_t b = sched.clears[k] * B, e = std::min(a.n, b + B);
      std::fill(a.force + D * b, a.force + D * e, 0.0);
      if constexpr (Friction) std::fill(a.torque + R * b, a.torque + R * e, 0.0);
    }
    pair_block<D, Hertz, Friction, Affine, Mat>(a, blk);
  };
  double* cost = sc.block_cost[DemWorkspace::kPairLoop].data();
  if (!then) return run_pair_schedule(sched, sc.shares, cost, block);
  // Each grain block's largest displacements, then their maxima (kick_drift's).
  std::vector<std::array<double, 2>>& disp = sc.block_disp;
  disp.assign(sched.n_before.size(), {0.0, 0.0});
  run_pair_schedule(sched, sc.shares, cost, block, [&](int32_t g) {
    constexpr int64_t B = PairSchedule::kBlock;
    disp[g] = (*then)(g * B, std::min(s.n, (g + 1) * B));
  });
  std::array<double, 2> most{0.0, 0.0};
  for (const std::array<double, 2>& d : disp) max_into(most, d);
  s.nbr_max_disp = std::sqrt(most[0]);
  s.nbr_step_disp = std::sqrt(most[1]);
}

template <int D>
void dispatch(const Model& m, State& s, DemWorkspace& w, const GrainBlockPass* then) {
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const bool fr = m.pair_friction();
  const bool aff = m.deforming_box();
  const bool mat = !m.pair_contact.empty();
#define SILT_CASE(H, F, A)                                        \
  if (hertz == H && fr == F && aff == A) {                        \
    if (mat) return pair_forces<D, H, F, A, true>(m, s, w, then); \
    return pair_forces<D, H, F, A, false>(m, s, w, then);         \
  }
  SILT_CASE(false, false, false)
  SILT_CASE(false, true, false)
  SILT_CASE(true, false, false)
  SILT_CASE(true, true, false)
  SILT_CASE(false, false, true)
  SILT_CASE(false, true, true)
  SILT_CASE(true, false, true)
  SILT_CASE(true, true, true)
#undef SILT_CASE
}

}  // namespace

void contact_forces(const Model& m, State& s, DemWorkspace& w, const GrainBlockPass* then) {
  // Pre: update_neighbors left a valid list (its postcondition).
  SILT_ASSERT(has_pair_list(s), "contact_forces needs a valid pair list");
  if (m.dim == 2) dispatch<2>(m, s, w, then);
  else dispatch<3>(m, s, w, then);
}

}  // namespace silt::dem
