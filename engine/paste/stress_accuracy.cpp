#include "paste/stress_accuracy.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/parallel.hpp"
#include "dem/stress.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt::paste {
namespace {

// The sums over the connections of f_a (r_i - r_j)_b, f the force on i from j of connection_force
// (its lubrication and, with implicit contacts, the contact's increment), in
// dem::pair_virial_sums's form; for two sets of local unknowns at once (G made once for both), x's
// with the imposed shear rate `rate` (the first 9 sums) and y's with none (the last 9), both in the
// units of the solve.
std::array<double, 18> connection_virials(const SystemLayout& L, const std::vector<Connection>& cs,
                                          const std::vector<double>& radius, const linalg::Vector& x,
                                          const linalg::Vector& y, const UnknownScale& units, double rate,
                                          bool implicit) {
  const int D = L.dim, nl = local_size(L);
  return deterministic_sums<18>(static_cast<int64_t>(cs.size()), 1024, [&](int64_t lo, int64_t hi) {
    std::array<double, 18> acc{};
    double g[3 * 16], tan[2][3], ux[16], uy[16], f[3], fc[3];
    for (int64_t k = lo; k < hi; ++k) {
      const Connection& c = cs[k];
      local_map(L, c, radius[c.i], radius[c.j], g);
      tangents(D, c.n, tan);
      for (int q = 0; q < nl; ++q) {
        const int64_t at = local_to_global(L, c, q);
        ux[q] = at >= 0 ? x[at] * units.of(at) : rate;
        uy[q] = at >= 0 ? y[at] * units.of(at) : 0.0;
      }
      const bool stiff = implicit && (c.k_n > 0 || c.k_t > 0);
      for (int set = 0; set < 2; ++set) {
        fc[0] = fc[1] = fc[2] = 0;
        connection_force_with(L, c, g, tan, set == 0 ? ux : uy, f, stiff ? fc : nullptr);
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) acc[9 * set + 3 * a + b] -= (f[a] + fc[a]) * c.r[b];
      }
    }
    return acc;
  });
}

double frobenius(const std::array<double, 9>& v) {
  double sum = 0;
  for (double e : v) sum += e * e;
  return std::sqrt(sum);
}

// The estimated error of the grains' stress after a solve of A x = b, relative to the stress: the
// lubrication (and implicit contacts') stress of the solver's error estimate over that of the
// contacts and of x.
double stress_error(const Model& m, const PasteParams& p, const SystemLayout& L, const std::vector<Connection>& cs,
                    const State& s, const UnknownScale& units, const linalg::SparseMatrix& A, const linalg::Vector& b,
                    const linalg::Vector& x, PasteWorkspace& w) {
  w.solver.error_estimate(A, b, x, w.error);
  const std::array<double, 18> lub =
      connection_virials(L, cs, s.particle_r, x, w.error, units, s.shear_rate, p.implicit_contacts);
  std::array<double, 9> total = dem::pair_virial_sums(s, s.pair_f.data()), error{};
  for (size_t k = 0; k < total.size(); ++k) {
    total[k] += lub[k];
    error[k] = lub[9 + k];
  }
  // Against the stress, or the scene's own stress where that is larger (the imposed pressure, the
  // viscous stress eta gammadot): a stress that cancels to round-off (a few grains turning alone) is
  // not asked for digits it does not have.
  double volume = 1;
  for (int a = 0; a < s.dim; ++a) volume *= s.box.len[a];
  const double imposed =
      std::max(m.box_control.on ? std::abs(m.box_control.pressure) : 0.0, viscous_stress(m, p.eta, s.shear_rate));
  const double scale = std::max(frobenius(total), imposed * volume), err = frobenius(error);
  return scale > 0 ? err / scale : 0.0;
}

}  // namespace

double solve_for_stress(const Model& m, const PasteParams& p, const SystemLayout& L, const std::vector<Connection>& cs,
                        const State& s, const UnknownScale& units, const linalg::SparseMatrix& A,
                        const linalg::Vector& b, linalg::Vector& x, PasteWorkspace& w, linalg::SolveReport& rep) {
  constexpr int kRounds = 8;  // (enough to reach kLowest from 1e-8 by tenths)
  constexpr double kLowest = 1e-15;
  double error = stress_error(m, p, L, cs, s, units, A, b, x, w);
  linalg::SolverSettings tighter = p.solver;
  // The rounds share what lubrication.max_iterations leaves (it bounds the whole solve), each at
  // most 4 times the first part's iterations (200 at least): a preconditioner that cannot reach the stress (Jacobi's
  // at h_min/a = 1e-12 took 547,228 iterations for one step under a limit of 1e7) leaves it short,
  // said, instead of running on.
  const int per_round = std::max(200, 4 * rep.iterations);
  for (int round = 0; round < kRounds && error > p.stress_tolerance && tighter.options.tolerance > kLowest &&
                      rep.iterations < p.solver.options.max_iterations;
       ++round) {
    tighter.options.tolerance =
        std::max(kLowest, tighter.options.tolerance * std::clamp(0.1 * p.stress_tolerance / error, 1e-4, 0.1));
    tighter.options.max_iterations = std::min(per_round, p.solver.options.max_iterations - rep.iterations);
    w.solver.set_settings(tighter);
    const linalg::Vector before = x;
    const linalg::SolveReport again = w.solver.solve(A, b, x, false);
    rep.iterations += again.iterations;
    if (!(again.residual < rep.residual)) {
      x = before;
      break;
    }
    rep.residual = again.residual;
    error = stress_error(m, p, L, cs, s, units, A, b, x, w);
    if (!again.ok()) break;  // (its estimate stale: the next round would start from a failed solve)
  }
  w.solver.set_settings(p.solver);
  return error;
}

std::string stress_notice(const Model& m, const State& s) {
  const std::vector<double>& v = s.module_field(paste_fields().solver);
  if (v.size() != kSolverStats) return "";
  const int bits = stress_notice_bits(v[kStressNotice]);
  if ((bits & 2) == 0) return "";
  const PasteParams& p = m.params.get<PasteParams>();
  if ((bits & 1) == 0)  // (within now)
    return "the grains' stress is within lubrication.stress_tolerance = " + format_number(p.stress_tolerance) +
           " again";
  return "the grains' stress is accurate to about " + format_number(v[kStressError]) +
         " of its size only (lubrication.stress_tolerance = " + format_number(p.stress_tolerance) +
         "): at h_min/a = " + format_number(p.h_min_over_a) +
         " the lubrication multiplies the velocities' error by up to a / h_min, and the solve went on to a residual "
         "of " +
         format_number(v[kLastResidual]) +
         ", as low as it could (round-off, or lubrication.max_iterations); the velocities are as accurate as that "
         "residual, the stress observables are not (lubrication.solver = \"direct\" solves to round-off, at a "
         "factorisation a step; or a larger h_min/a)";
}

}  // namespace silt::paste
