#include "fluid/step.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/parallel.hpp"
#include "core/simd_level.hpp"
#include "fluid/boundaries.hpp"
#include "fluid/operators.hpp"
#include "fluid/pressure_solve.hpp"
#include "fluid/stencil_kernels.hpp"
#include "silt/text.hpp"

namespace silt::fluid {
namespace {

// Wray's low-storage RK3.
constexpr double kGamma[3] = {8.0 / 15.0, 5.0 / 12.0, 3.0 / 4.0};
constexpr double kZeta[3] = {0.0, -17.0 / 60.0, -5.0 / 12.0};

// The maxima of |x| as the bits of |x|: for non-negative doubles their order is the integers',
// and a NaN's bits are above infinity's, so a NaN stays; integer maxima vectorise.
constexpr uint64_t kAbs = ~(uint64_t{1} << 63);

// One row of a store: s = p * scale, the largest |p| into m and, with kChange, the largest |s|
// before and |new - old| into m_old and change. The arrays never overlap (restrict: without it GCC
// leaves the 512-bit loop scalar).
template <bool kChange>
inline void store_row(const double* __restrict p, double* __restrict s, int64_t n, double scale, uint64_t& m,
                      uint64_t& m_old, uint64_t& change) {
  uint64_t lm = m, lo = m_old, lc = change;  // in registers: the loop is then a reduction
  for (int64_t i = 0; i < n; ++i) {
    const double v = p[i], nv = v * scale;
    if constexpr (kChange) {
      const uint64_t o = std::bit_cast<uint64_t>(s[i]) & kAbs;
      const uint64_t c = std::bit_cast<uint64_t>(nv - s[i]) & kAbs;
      lo = o > lo ? o : lo;
      lc = c > lc ? c : lc;
    }
    s[i] = nv;
    const uint64_t av = std::bit_cast<uint64_t>(v) & kAbs;
    lm = av > lm ? av : lm;
  }
  m = lm, m_old = lo, change = lc;
}

// Copies between the State's arrays (no ghosts) and the padded ones, multiplying by `scale` (a
// load leaves the ghosts as they were). A store returns the largest |value| of the padded array
// (NaN if any is) and, with kChange, the largest |value| the State held before and the largest
// change |new - old| it makes (both 0 without).
template <bool kLoad, bool kChange = false>
std::array<double, 3> copy_state(const Grid& g, const Layout& L, int a, std::vector<double>& state, double* padded,
                                 double scale = 1.0) {
  const auto d = a < 0 ? g.n : g.face_dims(a);
  return parallel_max<3>(d[1] * d[2], 8, [&](int64_t b, int64_t e) {
    uint64_t m = 0, m_old = 0, change = 0;
    // One choice of the instruction set for the whole block of rows.
    run_simd([&] {
      for (int64_t row = b; row < e; ++row) {
        const int64_t j = row % d[1], k = row / d[1];
        double* p = padded + L.at(0, j, k);
        double* s = state.data() + row * d[0];
        if constexpr (kLoad) scaled_copy(s, p, d[0], scale);
        else store_row<kChange>(p, s, d[0], scale, m, m_old, change);
      }
    });
    return std::array<double, 3>{std::bit_cast<double>(m), std::bit_cast<double>(m_old), std::bit_cast<double>(change)};
  });
}

void prepare(const FluidParams& p, FluidWorkspace& w) {
  const Grid& g = p.grid;
  w.L = Layout(g);
  for (int a = 0; a < 3; ++a) {
    const size_t n = a < g.dim ? static_cast<size_t>(w.L.size) : 0;
    w.u[a].assign(n, 0);
    w.u_star[a].assign(n, 0);
    w.n_prev[a].assign(n, 0);
    w.bc_lap[a].assign(n, 0);
  }
  w.bc_lap_ready = false;
  w.phi.assign(static_cast<size_t>(w.L.size), 0);
  w.p_kin.assign(static_cast<size_t>(w.L.size), 0);
  w.cells.assign(static_cast<size_t>(g.cells()), 0);
  int64_t most = g.cells();
  for (int a = 0; a < g.dim; ++a) {
    const auto d = unknown_dims(g, a);
    most = std::max(most, d[0] * d[1] * d[2]);
  }
  w.unknowns.assign(static_cast<size_t>(most), 0);
  w.drive_beta = {};  // the flow-rate drive's shapes belong to the grid and solvers made here
  make_pressure_solver(p, w);
  if (p.viscous != Viscous::kExplicit)
    for (int a = 0; a < g.dim; ++a) w.helmholtz[a] = make_helmholtz_solver(g, a);
  w.ready = true;
}

// The part of Lap u_a that the boundary values give (a moving lid, an inflow): the Laplacian of
// a field zero inside with the ghosts and boundary faces of the conditions. The implicit solve
// uses homogeneous conditions; this goes into its right-hand side.
void boundary_laplacian(const Grid& g, FluidWorkspace& w) {
  // u_star as the zero field: the momentum stage writes every entry of it that is read after.
  Padded z{};
  for (int a = 0; a < g.dim; ++a) {
    std::fill(w.u_star[a].begin(), w.u_star[a].end(), 0.0);
    z[a] = w.u_star[a].data();
  }
  fill_velocity_ghosts(g, w.L, z);
  for (int a = 0; a < g.dim; ++a) component_laplacian(g, w.L, a, z[a], w.bc_lap[a].data());
}

// The velocities of the faces (walls, lids, inflows): the boundary Laplacian is made again
// only when they change (a steered lid).
std::array<double, 18> boundary_velocities(const Grid& g) {
  std::array<double, 18> v{};
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      for (int c = 0; c < 3; ++c) v[9 * side + 3 * a + c] = g.bc[a][side].velocity[c];
  return v;
}

double alpha_of(int k) { return kGamma[k] + kZeta[k]; }

// The implicit viscous solve's coefficient in substep k: (1 - beta Lap) u* = rhs.
double implicit_beta(const FluidParams& p, int k, double dt) {
  const double theta = p.viscous == Viscous::kCrankNicolson ? 0.5 : 1.0;
  return theta * alpha_of(k) * dt * p.nu();
}

// The mean of n values, summed in fixed blocks (the same bits on any number of threads).
double deterministic_mean(const double* v, int64_t n) {
  const auto sum = deterministic_sums<1>(n, 4096, [&](int64_t b, int64_t e) {
    double s = 0;
    for (int64_t i = b; i < e; ++i) s += v[i];
    return std::array<double, 1>{s};
  });
  return sum[0] / static_cast<double>(n);
}

// The flow-rate drive: the mean of the driven component over its faces held at the imposed bulk
// velocity by a uniform forcing f, added as the substep's viscous solve would have taken it had it
// been in its right-hand side: u += f alpha dt r, r = 1 with an explicit viscous term and
// r = (1 - beta Lap)^-1 1 with an implicit one (smaller next to the walls, uniform along the
// periodic axes, so the velocity stays divergence-free). A uniform shift instead holds the rate
// too, but after an implicit solve its steady state is not the steady discrete profile: the wall
// rows get a forcing that the solve did not see, and the pressure gradient that holds the flow
// (and the profile) depended on the step (0.25 % low at dt = 0.01 in channel.toml with
// Crank-Nicolson, 0.49 % with backward Euler). Returns f alpha dt.
double hold_flow_rate(const FluidParams& p, FluidWorkspace& w) {
  const Grid& g = p.grid;
  const int a = p.drive_axis;
  const auto d = unknown_dims(g, a);
  const int64_t n = d[0] * d[1] * d[2];
  gather_unknowns(g, w.L, a, w.u[a].data(), w.unknowns.data());
  const double shift = p.bulk_velocity - deterministic_mean(w.unknowns.data(), n);
  const double beta = p.viscous == Viscous::kExplicit ? 0.0 : implicit_beta(p, w.substep, w.dt);
  if (beta == 0) {
    for (int64_t i = 0; i < n; ++i) w.unknowns[i] += shift;
    scatter_unknowns(g, w.L, a, w.unknowns.data(), w.u[a].data());
    return shift;
  }
  // (1/beta - Lap) r = 1/beta, by the viscous solve's transforms, once per substep's beta: at a fixed
  // step the same three shapes serve every step (solved each substep, they cost the flow-driven
  // channel.toml on 256 x 128 cells 58 % more time a step).
  const int k = w.substep;
  std::vector<double>& r = w.drive_shape[k];
  if (w.drive_beta[k] != beta || static_cast<int64_t>(r.size()) != n) {
    r.assign(static_cast<size_t>(n), 1 / beta);
    w.helmholtz[a]->solve(r.data(), 1 / beta);
    w.drive_beta[k] = beta;
    w.drive_mean[k] = deterministic_mean(r.data(), n);
  }
  const double forcing = shift / w.drive_mean[k];
  for (int64_t i = 0; i < n; ++i) w.unknowns[i] += forcing * r[i];
  scatter_unknowns(g, w.L, a, w.unknowns.data(), w.u[a].data());
  return forcing;
}

}  // namespace

FluidFields fluid_fields() {
  static const FluidFields f{{find_field("fluid_u")->id, find_field("fluid_v")->id, find_field("fluid_w")->id},
                             find_field("fluid_p")->id,
                             find_field("fluid_stat")->id};
  return f;
}

EventId cfl_event() {
  static const EventId e = register_module_event("fluid_cfl");
  return e;
}
EventId nonfinite_event() {
  static const EventId e = register_module_event("fluid_nonfinite");
  return e;
}
EventId solve_event() {
  static const EventId e = register_module_event("fluid_solve");
  return e;
}

size_t FluidWorkspace::bytes() const {
  size_t b = phi.capacity() + p_kin.capacity() + cells.capacity() + unknowns.capacity();
  for (int a = 0; a < 3; ++a)
    b += u[a].capacity() + u_star[a].capacity() + n_prev[a].capacity() + bc_lap[a].capacity() +
         drive_shape[a].capacity();
  return b * sizeof(double) + pressure_solver_bytes(*this);
}

double boundary_speed(const Grid& g, int a) {
  double v = 0;
  for (int b = 0; b < g.dim; ++b)
    for (int side = 0; side < 2; ++side) v = std::max(v, std::abs(g.bc[b][side].velocity[a]));
  return v;
}

double cfl_number(const FluidParams& p, const State& s, double dt) {
  const Grid& g = p.grid;
  const FluidFields f = fluid_fields();
  double rate = 0;
  for (int a = 0; a < g.dim; ++a) {
    const auto& u = s.module_field(f.u[a]);
    const auto mx = parallel_max<1>(static_cast<int64_t>(u.size()), 4096, [&](int64_t b, int64_t e) {
      double m = 0;
      for (int64_t i = b; i < e; ++i) {
        const double v = std::abs(u[i]);
        m = (v > m || v != v) ? v : m;  // a NaN stays
      }
      return std::array<double, 1>{m};
    });
    rate += std::max(mx[0], boundary_speed(g, a)) / g.h[a];  // a NaN of the field stays
  }
  return dt * rate;
}

FastestFace fastest_face(const FluidParams& p, const State& s) {
  const Grid& g = p.grid;
  FastestFace out;
  double best = -1;
  int64_t at = -1;
  for (int a = 0; a < g.dim; ++a) {
    const auto& u = s.module_field(fluid_fields().u[a]);
    for (int64_t q = 0; q < static_cast<int64_t>(u.size()); ++q) {  // (a failure's, once: serial)
      const double rate = std::isfinite(u[q]) ? std::abs(u[q]) / g.h[a] : HUGE_VAL;
      if (rate > best) {
        best = rate;
        out.axis = a;
        at = q;
        out.u = u[q];
      }
      if (rate == HUGE_VAL) break;
    }
    if (best == HUGE_VAL) break;
  }
  if (out.axis < 0) return out;
  const auto d = g.face_dims(out.axis);
  const std::array<int64_t, 3> idx{at % d[0], (at / d[0]) % d[1], at / (d[0] * d[1])};
  for (int b = 0; b < g.dim; ++b) {
    out.cell[b] = std::min(idx[b], g.n[b] - 1);
    out.x[b] = g.lo[b] + (static_cast<double>(idx[b]) + (b == out.axis ? 0.0 : 0.5)) * g.h[b];
  }
  return out;
}

std::string face_text(const Model& m, const FastestFace& f) {
  if (f.axis < 0) return "";
  std::string cell, x;
  for (int b = 0; b < m.dim; ++b) {
    cell += (b ? ", " : "") + std::to_string(f.cell[b]);
    x += (b ? ", " : "") + format_number(f.x[b], 4);
  }
  return " at cell (" + cell + "), x = (" + x + ")" + m.unit("m") + ": " + std::string(1, "uvw"[f.axis]) + " = " +
         format_number(f.u, 4) + m.unit("m/s");
}

double slowest_viscous_rate(const FluidParams& p) {
  const Grid& g = p.grid;
  double k2 = HUGE_VAL;
  for (int a = 0; a < g.dim; ++a) {
    const double k = (g.periodic(a) ? 2 : 1) * std::numbers::pi / (g.n[a] * g.h[a]);
    k2 = std::min(k2, k * k);
  }
  return p.nu() * k2;
}

double viscous_dt_limit(const FluidParams& p) {
  if (!(p.nu() > 0)) return HUGE_VAL;
  if (p.viscous == Viscous::kExplicit) return 0.9 * FluidParams::kViscousLimit / (p.nu() * p.grid.inv_h2_sum());
  if (p.viscous == Viscous::kCrankNicolson) return FluidParams::kCnModeLimit / slowest_viscous_rate(p);
  return HUGE_VAL;
}

double adaptive_dt(const FluidParams& p, double rate) {
  const double dt = rate > 0 ? p.cfl_target / rate : p.dt_max;
  return std::min({dt, viscous_dt_limit(p), p.dt_max});
}

double next_dt(const Model& m, const State& s) {
  const FluidParams& p = m.params.get<FluidParams>();
  if (p.dt_fixed) return p.dt;
  // From the velocity of the state (kRate) under the parameters of now, so that a target CFL or
  // a viscosity steered between steps acts at the next step; a state no step has stored yet
  // (kDtNext still 0) takes the model's first step.
  const auto& stat = s.module_field(fluid_fields().stat);
  const bool stored = stat.size() > kRate && stat[kDtNext] > 0;
  const double dt = stored ? adaptive_dt(p, step_rate(p, s)) : p.dt;
  return m.n_grains > 0 ? std::min(dt, m.dt) : dt;  // grains in the same step keep theirs
}

void fluid_dt(const Model& m, State& s) { s.dt = next_dt(m, s); }

double boundary_rate(const Grid& g) {
  double r = 0;
  for (int a = 0; a < g.dim; ++a) r += boundary_speed(g, a) / g.h[a];
  return r;
}

namespace {

// The Taylor-Green vortex's wavenumbers k = 2 pi / L per axis, and the grid's derivative of
// sin(k x), 2 sin(k h / 2) / h: for its field (initial_velocity) and its rate (vortex_rate).
std::pair<std::array<double, 3>, std::array<double, 3>> vortex_wavenumbers(const Grid& g) {
  std::array<double, 3> k{}, grid_k{};
  for (int a = 0; a < g.dim; ++a) {
    k[a] = 2 * std::numbers::pi / (g.n[a] * g.h[a]);
    grid_k[a] = 2 * std::sin(k[a] * g.h[a] / 2) / g.h[a];
  }
  return {k, grid_k};
}

}  // namespace

double vortex_rate(const FluidParams& p) {
  if (p.initial != Initial::kTaylorGreen) return 0;
  const Grid& g = p.grid;
  // Its largest |u| and |v| on their faces: a product of one factor per axis, each at its own
  // index, so the largest of each 1D factor, sin at the faces along the component's axis and cos
  // at the cell centres along the others.
  // (no structured bindings: the lambdas below capture these, which clang 14 refuses)
  const auto wavenumbers = vortex_wavenumbers(g);
  const std::array<double, 3>&k = wavenumbers.first, &grid_k = wavenumbers.second;
  auto largest = [&](int axis, bool face) {
    double best = 0;
    for (int64_t i = 0; i < g.n[axis]; ++i) {
      const double x = (static_cast<double>(i) + (face ? 0.0 : 0.5)) * g.h[axis];
      best = std::max(best, std::abs(face ? std::sin(k[axis] * x) : std::cos(k[axis] * x)));
    }
    return best;
  };
  double rate = 0;
  for (int a = 0; a < 2; ++a) {
    double m = std::abs(p.initial_velocity) * (a == 0 ? 1.0 : std::abs(grid_k[0] / grid_k[1]));
    for (int b = 0; b < g.dim; ++b) m *= largest(b, b == a);
    rate += m / g.h[a];
  }
  return rate;
}

double known_rate(const FluidParams& p, std::string* what) {
  const Grid& g = p.grid;
  double rate = 0;
  bool walls = false, drive = false;
  for (int a = 0; a < g.dim; ++a) {
    const double wall = boundary_speed(g, a);
    const double bulk = p.drive == Drive::kFlowRate && a == p.drive_axis ? std::abs(p.bulk_velocity) : 0.0;
    rate += std::max(wall, bulk) / g.h[a];
    walls |= wall > 0 && wall >= bulk;
    drive |= bulk > wall;
  }
  if (what)
    *what = walls && drive ? "the walls' and inflows' speeds and the bulk velocity (fluid.bulk_velocity) alone give"
            : drive        ? "the bulk velocity (fluid.bulk_velocity) alone gives"
                           : "the walls' and inflows' speeds alone give";
  return rate;
}

double step_rate(const FluidParams& p, const State& s) {
  const auto& stat = s.module_field(fluid_fields().stat);
  return std::max(stat.size() > kRate ? stat[kRate] : 0.0, boundary_rate(p.grid));
}

double change_rate(const FluidParams& p, const State& s) {
  const auto& stat = s.module_field(fluid_fields().stat);
  return stat.size() > kChangeRate ? stat[kChangeRate] * p.length_scale / p.velocity_scale : 0.0;
}

bool is_steady(const FluidParams& p, const State& s) { return change_rate(p, s) < p.steady_tol; }

void initial_velocity(const Model& m, State& s) {
  const FluidParams& p = m.params.get<FluidParams>();
  const FluidFields f = fluid_fields();
  const Grid& g = p.grid;
  auto& stat = s.module_field(f.stat);
  stat.assign(kStatCount, 0.0);
  // The rate of the state (a fluid at rest: its walls' and inflows', which the first step's CFL
  // number is). Taken again below with the vortex.
  stat[kRate] = cfl_number(p, s, 1.0);
  if (p.initial != Initial::kTaylorGreen) return;
  // u = U0 sin(kx x) cos(ky y) cos(kz z), v = -c U0 cos sin cos, w = 0, with k = 2 pi / L per axis
  // and c = kx / ky (1 in a square box) as the grid has it: c = D_x / D_y, D_a = 2 sin(k_a h_a / 2) / h_a
  // the grid's derivative of sin(k_a x_a), so that the sampled field is divergence-free on the grid
  // (in a box with Lx != Ly too).
  const auto wavenumbers = vortex_wavenumbers(g);
  const std::array<double, 3>&k = wavenumbers.first, &grid_k = wavenumbers.second;
  const double c = grid_k[0] / grid_k[1];
  for (int a = 0; a < 2; ++a) {
    auto& u = s.module_field(f.u[a]);
    const auto d = g.face_dims(a);
    for (int64_t kk = 0; kk < d[2]; ++kk)
      for (int64_t j = 0; j < d[1]; ++j)
        for (int64_t i = 0; i < d[0]; ++i) {
          const std::array<int64_t, 3> idx{i, j, kk};
          std::array<double, 3> x{};
          for (int b = 0; b < g.dim; ++b)
            x[b] = g.lo[b] + (static_cast<double>(idx[b]) + (b == a ? 0.0 : 0.5)) * g.h[b];
          const double cz = g.dim == 3 ? std::cos(k[2] * x[2]) : 1.0;
          const double v = a == 0 ? std::sin(k[0] * x[0]) * std::cos(k[1] * x[1])
                                  : -c * std::cos(k[0] * x[0]) * std::sin(k[1] * x[1]);
          u[i + d[0] * (j + d[1] * kk)] = p.initial_velocity * v * cz;
        }
  }
  stat[kRate] = cfl_number(p, s, 1.0);
}

namespace {

Padded pointers(const Grid& g, std::array<LargeArray<double>, 3>& v) {
  Padded out{};
  for (int a = 0; a < g.dim; ++a) out[a] = v[a].data();
  return out;
}

}  // namespace

void fluid_load(const Model& m, State& s, FluidWorkspace& w) {
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  const FluidFields f = fluid_fields();
  if (!w.ready || w.L.n != g.n) prepare(p, w);
  w.substep = 0;
  w.failed = true;  // until the checks below pass
  w.drive = 0;
  w.dt = s.dt;
  auto& stat = s.module_field(f.stat);
  if (stat.size() == kStatCount - 1) stat.push_back(0.0);  // a checkpoint of before kChangeRate
  if (stat.size() != kStatCount) {                         // a state made without the fluid's numbers
    stat.assign(kStatCount, 0.0);
    stat[kRate] = cfl_number(p, s, 1.0);
  }
  const double dt = s.dt, nu = p.nu();
  // Stability of the scheme with this step (an adaptive step is within it by construction), with
  // the walls' and inflows' velocities as they are now (a lid steered faster since the last step).
  const double cfl = dt * step_rate(p, s);
  stat[kCfl] = cfl;
  if (!(cfl <= FluidParams::kCflLimit)) {
    s.events.slot[cfl_event()].raise(0, cfl);
    return;
  }
  if (p.viscous == Viscous::kExplicit) {
    const double inv = g.inv_h2_sum();
    if (nu * dt * inv > FluidParams::kViscousLimit) {
      s.events.slot[cfl_event()].raise(1, nu * dt * inv);
      return;
    }
  }
  for (int a = 0; a < g.dim; ++a) copy_state<true>(g, w.L, a, s.module_field(f.u[a]), w.u[a].data());
  if (p.viscous != Viscous::kExplicit && (!w.bc_lap_ready || w.bc_velocities != boundary_velocities(g))) {
    boundary_laplacian(g, w);
    w.bc_velocities = boundary_velocities(g);
    w.bc_lap_ready = true;
  }
  // The pressure so far (kinematic, p / rho), whose gradient the predictor takes.
  auto& ps = s.module_field(f.p);
  copy_state<true>(g, w.L, -1, ps, w.p_kin.data(), 1 / p.density);
  w.failed = false;
}

void fluid_momentum(const Model& m, State&, FluidWorkspace& w) {
  if (w.failed) return;
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  const int k = w.substep;
  const bool implicit = p.viscous != Viscous::kExplicit;
  SubstepCoefficients sc;
  if (p.drive == Drive::kPressure) sc.force[p.drive_axis] = p.pressure_gradient / p.density;
  sc.viscous = p.viscous;
  sc.nu = implicit ? 0.0 : p.nu();
  sc.gdt = kGamma[k] * w.dt;
  sc.zdt = kZeta[k] * w.dt;
  sc.adt = alpha_of(k) * w.dt;
  sc.p = w.p_kin.data();
  fill_pressure_ghosts(g, w.L, w.p_kin.data());
  // Crank-Nicolson: (1 - beta Lap) u* = u + dt (gamma N + zeta N') + beta Lap u + beta Lap_bc,
  // beta = alpha dt nu / 2; backward Euler: (1 - beta Lap) u* = u + dt (gamma N + zeta N') +
  // beta Lap_bc, beta = alpha dt nu. fluid_viscous solves it.
  sc.beta = implicit ? implicit_beta(p, k, w.dt) : 0.0;
  const Padded u = pointers(g, w.u);
  fill_velocity_ghosts(g, w.L, u);
  momentum_substep(g, w.L, {u[0], u[1], u[2]}, pointers(g, w.u_star), pointers(g, w.n_prev),
                   {w.bc_lap[0].data(), w.bc_lap[1].data(), w.bc_lap[2].data()}, sc);
  if (!implicit)
    for (int a = 0; a < g.dim; ++a) std::swap(w.u[a], w.u_star[a]);
}

void fluid_viscous(const Model& m, State&, FluidWorkspace& w) {
  if (w.failed) return;
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  const double beta = implicit_beta(p, w.substep, w.dt);
  // (1/beta - Lap) u* = rhs / beta, per component on its own faces.
  if (beta > 0) {
    const double inv_beta = 1 / beta;
    for (int a = 0; a < g.dim; ++a) {
      // Read from u* and written back by the solve's passes along x.
      const SolveRows rows = unknown_rows(g, w.L, a, w.u_star[a].data());
      w.helmholtz[a]->solve(w.unknowns.data(), inv_beta, {&rows, inv_beta, &rows});
    }
  }
  for (int a = 0; a < g.dim; ++a) std::swap(w.u[a], w.u_star[a]);
}

void fluid_pressure(const Model& m, State& s, FluidWorkspace& w) {
  if (w.failed) return;
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  // Lap phi = div u* / (alpha dt).
  const Padded u = pointers(g, w.u);
  fill_velocity_ghosts(g, w.L, u);
  divergence(g, w.L, {u[0], u[1], u[2]}, w.cells.data(), -1 / (alpha_of(w.substep) * w.dt));
  const linalg::SolveReport r = solve_pressure(p, w);
  auto& stat = s.module_field(fluid_fields().stat);
  if (!r.ok()) {
    s.events.slot[solve_event()].raise(static_cast<int64_t>(r.status), r.residual);
    w.failed = true;
    return;
  }
  stat[kIters] = r.iterations;
  stat[kResidual] = r.residual;
  stat[kSolves] += 1;
  stat[kItersSum] += r.iterations;
  stat[kItersMax] = std::max<double>(stat[kItersMax], r.iterations);
}

void fluid_project(const Model& m, State&, FluidWorkspace& w) {
  if (w.failed) return;
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  // u = u* - alpha dt grad phi; p += phi.
  fill_pressure_ghosts(g, w.L, w.phi.data());
  project_velocity(g, w.L, pointers(g, w.u), w.phi.data(), alpha_of(w.substep) * w.dt, w.p_kin.data());
  if (p.drive == Drive::kFlowRate) w.drive += hold_flow_rate(p, w) / w.dt;
  ++w.substep;
}

void fluid_store(const Model& m, State& s, FluidWorkspace& w) {
  if (w.failed) return;
  const FluidParams& p = m.params.get<FluidParams>();
  const Grid& g = p.grid;
  const FluidFields f = fluid_fields();
  auto& stat = s.module_field(f.stat);
  const Padded u = pointers(g, w.u);
  // The periodic copies of the faces, and the largest divergence when something looks at the
  // end of this step (a sample, a frame): a pass over the grid the dynamics do not need.
  fill_velocity_ghosts(g, w.L, u);
  double div_max = 0;
  if (s.boundary_seen) div_max = divergence_max(g, w.L, {u[0], u[1], u[2]}, w.cells.data());
  // sum_a max |u_a| / h_a from the values stored (and the boundaries' velocities), and how much they changed: max
  // |u^(n+1) - u^n| over max(max |u^(n+1)|, max |u^n|), 0 for a fluid at rest throughout. Every step, so that the last
  // state of any run has it: the old values are read in the pass that overwrites them.
  double rate = 0, speed = 0, change = 0;
  for (int a = 0; a < g.dim; ++a) {
    const auto r = copy_state<false, true>(g, w.L, a, s.module_field(f.u[a]), u[a]);
    rate += std::max(r[0], boundary_speed(g, a)) / g.h[a];  // as cfl_number(): a NaN stays
    speed = std::max({speed, r[0], r[1]});
    change = std::max(change, r[2]);
  }
  // p = rho p_kin.
  auto& ps = s.module_field(f.p);
  copy_state<false>(g, w.L, -1, ps, w.p_kin.data(), p.density);
  if (s.boundary_seen) stat[kDivMax] = div_max;
  stat[kChangeRate] = speed > 0 ? change / (speed * w.dt) : 0.0;
  stat[kDriveGradient] = p.drive == Drive::kFlowRate ? w.drive * p.density : p.pressure_gradient;
  stat[kCellSteps] += static_cast<double>(g.cells());
  stat[kRate] = rate;
  if (!std::isfinite(rate) || !std::isfinite(div_max)) {
    s.events.slot[nonfinite_event()].raise(0, rate);
    return;
  }
  // Finite, but so fast that the squares over the grid overflow (a pressure gradient of 1e155 Pa/m
  // in one step). Refused as the scene's speeds are (check_speed), so that the last good state is
  // the one before.
  if (g.squares_overflow(rate, p.density)) {
    s.events.slot[nonfinite_event()].raise(1, rate);
    return;
  }
  stat[kDtNext] = p.dt_fixed ? p.dt : adaptive_dt(p, rate);
}

}  // namespace silt::fluid
