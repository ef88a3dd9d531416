#include "paste/solve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/parallel.hpp"
#include "dem/forces_under.hpp"
#include "dem/stress.hpp"
#include "measure/equilibrium.hpp"
#include "paste/contact_stiffness.hpp"
#include "paste/stress_accuracy.hpp"
#include "paste/unknown_scale.hpp"
#include "shear/cycle_origin.hpp"

namespace silt::paste {
namespace {

constexpr double kRollRegularisation = 1e-8;

// The matrix a factor was made from, kept in the state (paste_factor): n, nnz, the column
// starts, the rows and the values, as doubles.
void store_matrix(const linalg::SparseMatrix& a, std::vector<double>& out) {
  const int64_t n = a.cols(), nnz = a.nonZeros();
  out.resize(static_cast<size_t>(2 + (n + 1) + 2 * nnz));
  out[0] = static_cast<double>(n);
  out[1] = static_cast<double>(nnz);
  double* o = out.data() + 2;
  for (int64_t k = 0; k <= n; ++k) *o++ = a.outerIndexPtr()[k];
  for (int64_t k = 0; k < nnz; ++k) *o++ = a.innerIndexPtr()[k];
  for (int64_t k = 0; k < nnz; ++k) *o++ = a.valuePtr()[k];
}

linalg::SparseMatrix load_matrix(const std::vector<double>& in) {
  const auto n = static_cast<int64_t>(in[0]), nnz = static_cast<int64_t>(in[1]);
  linalg::SparseMatrix a(n, n);
  a.resizeNonZeros(nnz);
  const double* o = in.data() + 2;
  for (int64_t k = 0; k <= n; ++k) a.outerIndexPtr()[k] = static_cast<int>(*o++);
  for (int64_t k = 0; k < nnz; ++k) a.innerIndexPtr()[k] = static_cast<int>(*o++);
  for (int64_t k = 0; k < nnz; ++k) a.valuePtr()[k] = *o++;
  return a;
}

// Xi <- S Xi S and b <- S b in place.
void scale_system(const UnknownScale& u, linalg::SparseMatrix& a, linalg::Vector& b) {
  if (u.identity()) return;
  double* val = a.valuePtr();
  const int* rows = a.innerIndexPtr();
  const int* outer = a.outerIndexPtr();
  parallel_for(a.outerSize(), 1024, [&](int64_t lo, int64_t hi) {
    for (int64_t col = lo; col < hi; ++col) {
      const double sc = u.of(col);
      for (int q = outer[col]; q < outer[col + 1]; ++q) val[q] *= sc * u.of(rows[q]);
      b[col] *= sc;
    }
  });
}

// Largest change of an entry between two vectors, relative to the largest entry of the newer, or
// to `floor` where every entry is below it.
double relative_change(const double* now, const double* before, int64_t n, double floor = 0) {
  double top = floor, diff = 0;
  for (int64_t k = 0; k < n; ++k) {
    top = std::max(top, std::abs(now[k]));
    diff = std::max(diff, std::abs(now[k] - before[k]));
  }
  return top > 0 ? diff / top : 0;
}

// The largest entry of M V / dt over the grains' unknowns, in the units of the solve: the inertial
// part of the inertial stepper's right-hand side.
double momentum_rate(const State& s, const UnknownScale& units, int pg, double dt) {
  const int D = s.dim, R = s.rot;
  double top = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    if (!(s.particle_inv_m[i] > 0)) continue;
    for (int a = 0; a < D; ++a) top = std::max(top, std::abs(s.particle_v[D * i + a]) / (s.particle_inv_m[i] * dt));
    for (int a = 0; a < R; ++a)
      top = std::max(top, std::abs(s.particle_w[R * i + a]) / (s.particle_inv_i[i] * dt) * units.of(i * pg + D + a));
  }
  return top;
}

// The shortest viscous relaxation time m / xi of a moving grain (xi its largest translational
// diagonal entry of Xi, `val` holding Xi alone, and its Stokes drag); infinity where no grain moves
// or none is held.
double fastest_relaxation(const PasteParams& p, const State& s, const ResistanceSystem& system, const double* val,
                          int pg) {
  const int D = s.dim;
  double shortest = std::numeric_limits<double>::infinity();
  for (int64_t i = 0; i < s.n; ++i) {
    // (the Stokes drag, on the diagonal after this is read, holds a grain with no connection)
    double v2 = 0, xi = p.stokes_drag ? 6 * std::numbers::pi * p.eta * s.particle_r[i] : 0.0;
    for (int a = 0; a < D; ++a) {
      v2 += s.particle_v[D * i + a] * s.particle_v[D * i + a];
      xi = std::max(xi, val[system.diagonal_position(i * pg + a)]);
    }
    if (v2 > 0 && xi > 0 && s.particle_inv_m[i] > 0) shortest = std::min(shortest, 1 / (s.particle_inv_m[i] * xi));
  }
  return shortest;
}

// paste_alone: a flag, 1 when the set changed at this solve, then the ids of the grains alone in
// their component of the connection graph (held at the affine flow), in increasing order.
void record_alone(State& s, const std::vector<int32_t>& component, const std::vector<int64_t>& comp_size) {
  std::vector<double>& field = s.module_field(paste_fields().alone);
  std::vector<double> ids;
  for (int64_t i = 0; i < static_cast<int64_t>(component.size()); ++i)
    if (comp_size[component[i]] == 1) ids.push_back(s.particle_id[i]);
  std::sort(ids.begin(), ids.end());
  const bool same =
      !field.empty() && field.size() == ids.size() + 1 && std::equal(ids.begin(), ids.end(), field.begin() + 1);
  const bool was_empty = field.size() <= 1;
  field.resize(ids.size() + 1);
  std::copy(ids.begin(), ids.end(), field.begin() + 1);
  field[0] = same || (was_empty && ids.empty()) ? 0 : 1;
}

// The next step (sec. 2.2.4): grow while Xi's diagonal and the right-hand side change by at most
// dt_change a step, else shrink in proportion.
double next_step(const PasteParams& p, double dt, double change) {
  const double factor = change <= p.dt_change ? p.dt_growth : std::max(0.1, p.dt_change / change);
  return std::clamp(dt * factor, p.dt_min, p.dt_max);
}

}  // namespace

double fastest_rate(const State& s) {
  const int D = s.dim;
  double top = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    double v2 = 0;
    for (int a = 0; a < D; ++a) v2 += s.particle_v[D * i + a] * s.particle_v[D * i + a];
    top = std::max(top, v2 / (s.particle_r[i] * s.particle_r[i]));
  }
  if (top >= 0x1p-900) return std::sqrt(top);
  // Velocities so small that their squares fall below a double's range (a paste under a pressure
  // of 1e-200): by hypot, which does not square. (The squares read 0, and the drift bound let the
  // step grow until the grains overlapped.)
  top = 0;
  for (int64_t i = 0; i < s.n; ++i) {
    const double* v = &s.particle_v[D * i];
    top = std::max(top, std::hypot(v[0], v[1], D == 3 ? v[2] : 0.0) / s.particle_r[i]);
  }
  return top;
}

PasteFields paste_fields() {
  static const PasteFields f{
      find_field("pair_f_lub")->id,         find_field("paste_dt")->id,          find_field("paste_solver")->id,
      find_field("paste_change")->id,       find_field("paste_factor")->id,      find_field("paste_alone")->id,
      find_field("paste_coarse_order")->id, find_field("paste_dt_scale")->id,    find_field("paste_solved_under")->id,
      find_field("pair_f_implicit")->id,    find_field("paste_forces_under")->id};
  return f;
}

EventId solve_event() {
  static const EventId e = register_module_event("paste_solve");
  return e;
}

EventId resolve_event() {
  static const EventId e = register_module_event("paste_resolve");
  return e;
}

EventId mass_event() {
  static const EventId e = register_module_event("paste_mass");
  return e;
}

EventId step_event() {
  static const EventId e = register_module_event("paste_step");
  return e;
}

const char* stepper_name(Stepper s) { return s == Stepper::kInertial ? "inertial" : "quasi_static"; }

std::string alone_notice(const State& s) {
  const std::vector<double>& field = s.module_field(paste_fields().alone);
  if (field.empty() || field[0] != 1) return "";
  const size_t n = field.size() - 1;
  if (n == 0) return "every grain has a lubricated connection again";
  // The first ids, enough to find them (render.color_by = "id", p[K].x); then how many more.
  constexpr size_t kNamed = 20;
  std::string ids;
  for (size_t k = 0; k < std::min(n, kNamed); ++k)
    ids += (k ? ", " : "") + std::to_string(static_cast<int64_t>(field[k + 1]));
  if (n > kNamed) ids += " and " + std::to_string(n - kNamed) + " more";
  return std::string(n == 1 ? "grain " : "grains ") + ids + (n == 1 ? " has" : " have") +
         " no lubricated connection (no gap below lubrication.h_max_over_a): held at the affine flow, which is how "
         "the liquid carries a grain alone; lubrication.stokes_drag = true lets it move under a Stokes drag instead";
}

namespace {

// Whether the adaptive step stored in the state was chosen under another time scale than the
// model's (a viscosity, pressure or rate steered since): the ratio new / old, else 1.
double step_rescale(const PasteParams& p, const State& s) {
  const double was = s.module_field(paste_fields().dt_scale)[0];
  return !p.fixed_dt && was > 0 && p.step_scale > 0 && was != p.step_scale ? p.step_scale / was : 1.0;
}

// The parameters a quasi-static solve's velocities follow from besides the configuration: the
// liquid, the roughness, the imposed stresses and rate. (An array: compared at every step, kept at
// every solve, without allocating.)
std::array<double, 11> solve_parameters(const Model& m) {
  const PasteParams& p = m.params.get<PasteParams>();
  const BoxControl& b = m.box_control;
  return {p.eta,
          p.h_min_over_a,
          p.h_max_over_a,
          static_cast<double>(p.cutoff),
          p.stokes_drag ? 1.0 : 0.0,
          p.implicit_contacts ? 1.0 : 0.0,
          b.pressure,
          b.cycle_amplitude,
          b.cycle_omega,
          m.shear.rate,
          m.shear.stress};
}

// The step dt, shortened where the fastest grain (max |V_i| / r_i) would move more than drift_max of
// its radius in it, to no less than dt_min: the one rule of the first solve, of a solve again and of
// a state before its first step (which must agree to the bit).
double drift_bounded(const PasteParams& p, double fastest, double dt) {
  return fastest * dt > p.drift_max ? std::max(p.drift_max / fastest, p.dt_min) : dt;
}

// The first step of a run of the model from the state's velocities: dt_initial, shorter where they
// would move a grain farther than drift_max of its radius in it (as the first solve bounds it).
double first_step(const PasteParams& p, const State& s) {
  if (p.fixed_dt || p.drift_max <= 0) return p.dt_initial;
  return drift_bounded(p, fastest_rate(s), p.dt_initial);
}

// The step of the state (paste_dt), under the model's time scale (paste_dt, below); dt_initial in a
// state without one.
double state_step(const PasteParams& p, const State& s) {
  const double dt = s.module_field(paste_fields().dt)[0];
  if (dt <= 0) return p.dt_initial;
  // A steered time scale (a viscosity, pressure or rate changed): when it fell by r, the step of the
  // old scale would shear and move the grains 1 / r times too far a step (a viscosity lowered 1,000
  // times dilated a sheared paste by 5 % in 50 steps, no failure reported): the step falls with it.
  // When it rose, the velocities follow only as the contact forces do (a pressure lowered leaves the
  // grains pressed at the old one): the step stays, grows as the adaptive step lets it, and comes
  // within the new bounds. The velocities are solved again under the new parameters
  // (lubrication_resolve).
  // A quasi-static state before its first step starts as a run of the model from its velocities
  // would, under a steered scale or dt_initial too (`set lubrication.dt_initial 0.1` before the
  // first step was described and not taken). The inertial stepper carries its velocities over with
  // the step they were solved for, by the rule above.
  if (s.step == 0 && p.stepper == Stepper::kQuasiStatic) return first_step(p, s);
  const double r = step_rescale(p, s);
  return std::clamp(r < 1 ? dt * r : dt, p.dt_min, p.dt_max);
}

}  // namespace

void paste_dt(const Model& m, State& s) { s.dt = state_step(m.params.get<PasteParams>(), s); }

bool solved_under_other(const Model& m, const State& s) {
  const PasteParams& p = m.params.get<PasteParams>();
  if (p.stepper != Stepper::kQuasiStatic) return false;  // the inertial stepper's carry over
  const std::vector<double>& under = s.module_field(paste_fields().solved_under);
  // Empty: a checkpoint written before the parameters were kept; solved again only when its time
  // scale differs from the model's (what it records).
  const auto now = solve_parameters(m);
  if (under.empty() ? step_rescale(p, s) != 1.0 : !std::equal(under.begin(), under.end(), now.begin(), now.end()))
    return true;
  // The contact forces made again under a steered friction or material since the solve (empty: a
  // checkpoint written before either was kept).
  const std::vector<double>& with = s.module_field(paste_fields().forces_under);
  const std::vector<double>& forces = s.module_field(dem::forces_under_field());
  return !with.empty() && !forces.empty() && with != forces;
}

namespace {

// told: the run says what this solve leaves before any other solve (see kStressNotice).
void solve_paste(const Model& m, State& s, PasteWorkspace& w, SolveAt at, bool told) {
  const PasteParams& p = m.params.get<PasteParams>();
  const PasteFields f = paste_fields();
  const int D = s.dim, R = s.rot;
  const int64_t n = s.n;
  find_connections(s, p.law(), w.links);
  const std::vector<Connection>& cs = w.links.c;
  const SystemLayout L = make_layout(m, n);
  const UnknownScale units = unknown_scale(L, p.a);
  const int pg = L.per_grain;
  const int64_t size = L.size();
  w.system.assemble(L, cs, s.particle_r, s.shear_rate);
  linalg::SparseMatrix& A = w.system.matrix();
  double* val = A.valuePtr();

  // Right-hand side: contact forces and torques (contact_forces left their sums), the drive of
  // the imposed shear, and on the box rows A (sigma_cont - P) (compression positive).
  linalg::Vector b = w.system.shear_rhs();
  for (int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) b[i * pg + a] += s.particle_f[D * i + a];
    for (int a = 0; a < R; ++a) b[i * pg + D + a] += s.particle_t[R * i + a];
  }
  if (L.n_box > 0) {
    double vol = 1;
    for (int a = 0; a < D; ++a) vol *= s.box.len[a];
    const std::array<double, 9> vir = dem::pair_virial_sums(s, s.pair_f.data());
    const CycleOrigin origin = shear::cycle_origin(m, s);
    for (int k = 0; k < L.n_box; ++k) {
      const int a = L.box_axis[k];
      // The imposed stress at the time of this configuration (the clock advances after the solve).
      b[L.box_unknown(k)] +=
          vir[4 * a] - vol * m.box_control.stress(a, origin, at == SolveAt::kStep ? s.t + s.dt : s.t);
    }
  }

  // What the adaptive step watches: Xi's diagonal and the right-hand side of the configuration.
  std::vector<double>& change = s.module_field(f.change);
  double step_change = 0;
  {
    std::vector<double>& now = w.scratch;  // kept between steps: no allocation per step
    now.resize(static_cast<size_t>(2 * size));
    for (int64_t k = 0; k < size; ++k) {
      const double sk = units.of(k);  // in the units of the solve
      now[k] = val[w.system.diagonal_position(k)] * sk * sk;
      now[size + k] = b[k] * sk;
    }
    // The right-hand side's change is against its largest entry, or against the net force the
    // equilibrium criterion resolves (static_force) where every entry is below it: at rest the net
    // forces decay toward round-off, each step's decay read as a change of order one, and the step
    // shrank without end (paste_iso with implicit contacts, 600 eta/P past static: 900,000 steps,
    // down to 4e-4 eta/P). The floor binds only once the net forces are below the criterion's.
    // Not against a configuration solved under another time scale than the model's (steered): Xi
    // and the right-hand side changed with the parameters, not the configuration.
    // With inertia the solve's right-hand side is M V^n / dt + F, and the forces' change is against
    // it: a contact opening after a rebound brought its force toward zero, each step's decrease a
    // change of order one of the largest force, and the step shrank by 1 % a step to dt_min (two
    // disks meeting at 2 a/t, viscosity 1e-3: 2,449 steps, then a failure whatever was changed).
    // The forces then change by dt_change of m v / dt: the step is a fraction of the contacts' time.
    double floor = static_force(m);
    if (p.stepper == Stepper::kInertial && s.dt > 0) floor = std::max(floor, momentum_rate(s, units, pg, s.dt));
    if (change.size() == now.size() && step_rescale(p, s) == 1.0)
      step_change = std::max(relative_change(now.data(), change.data(), size),
                             relative_change(now.data() + size, change.data() + size, size, floor));
    change.swap(now);
  }

  // The step these velocities will move the grains by: the next one.
  const bool inertial = p.stepper == Stepper::kInertial;
  const double dt_field = s.module_field(f.dt)[0];
  // (the first solve of a state solved under another time scale: its step rescaled, as paste_dt would)
  double dt = at == SolveAt::kFirst ? (dt_field > 0 ? state_step(p, s) : p.dt_initial) : s.dt;
  // The inertial stepper's first step from moving grains: at most sqrt(dt_change) of the fastest
  // viscous relaxation m / xi among them, where the adaptive step keeps it afterwards (a coasting
  // grain's force -xi v changes by xi^2 v dt / m a step, dt_change of m v / dt at that step). Two
  // disks coasting at eta = 1 took a first step of dt_initial, 1e-3 of the shear time and 30 times
  // m / xi, which took their momentum away: they stopped at a gap 45 % larger than the closed form's.
  if (inertial && at == SolveAt::kFirst && !(dt_field > 0) && !p.fixed_dt)
    dt = std::max(p.dt_min, std::min(dt, std::sqrt(p.dt_change) * fastest_relaxation(p, s, w.system, val, pg)));
  const bool adapt = at == SolveAt::kStep && !p.fixed_dt;
  // The state's step before the first is the paste's (it showed the DEM's contact-time step).
  if (at == SolveAt::kFirst) s.dt = dt;
  double dt_next = adapt ? next_step(p, dt, step_change) : dt;
  if (p.implicit_contacts) {
    set_contact_stiffness(m, s, dt_next, w.links);
    w.system.add_contact_stiffness(cs, s.particle_r, s.shear_rate, b);
  }

  // Inertia, the optional Stokes drag: on the grains' diagonal. (With inertia, the lightest m / dt
  // against Xi's largest translational resistance, before it is added.)
  double lightest = std::numeric_limits<double>::infinity(), stiffest = 0;
  int64_t lightest_at = -1;
  for (int64_t i = 0; i < n; ++i) {
    const double r = s.particle_r[i];
    if (inertial) {
      for (int a = 0; a < D; ++a) stiffest = std::max(stiffest, val[w.system.diagonal_position(i * pg + a)]);
      if (const double md = 1 / (s.particle_inv_m[i] * dt); md < lightest) {
        lightest = md;
        lightest_at = i;
      }
    }
    double ct = p.stokes_drag ? 6 * std::numbers::pi * p.eta * r : 0;
    double cr = p.stokes_drag ? 8 * std::numbers::pi * p.eta * r * r * r : 0;
    if (inertial) {
      const double mass = 1 / s.particle_inv_m[i], inertia = 1 / s.particle_inv_i[i];
      ct += mass / dt;
      cr += inertia / dt;
      for (int a = 0; a < D; ++a) b[i * pg + a] += mass / dt * s.particle_v[D * i + a];
      for (int a = 0; a < R; ++a) b[i * pg + D + a] += inertia / dt * s.particle_w[R * i + a];
    }
    for (int a = 0; a < D; ++a) val[w.system.diagonal_position(i * pg + a)] += ct;
    for (int a = 0; a < R; ++a) val[w.system.diagonal_position(i * pg + D + a)] += cr;
  }

  if (inertial && lightest < kMassResolution * stiffest) {
    s.events[mass_event()].raise(s.particle_id[lightest_at], lightest / stiffest);
    return;
  }
  scale_system(units, A, b);

  // Without inertia or drag, Xi is singular by the translation of every connected cluster and by
  // every degree of freedom of a grain with no connection: each cluster's first grain has its
  // translation pinned (its mean velocity set to zero after the solve), a grain alone is held
  // still relative to the affine flow, which is how the liquid carries it.
  int32_t n_comp = 0;
  std::vector<int64_t> comp_size, comp_first;
  const bool pinning = !inertial && !p.stokes_drag;
  if (pinning) {
    w.component = connected_components(n, cs, n_comp);
    comp_size.assign(static_cast<size_t>(n_comp), 0);
    comp_first.assign(static_cast<size_t>(n_comp), -1);
    for (int64_t i = 0; i < n; ++i) {
      const int32_t c = w.component[i];
      ++comp_size[c];
      if (comp_first[c] < 0) comp_first[c] = i;
    }
    record_alone(s, w.component, comp_size);
    double scale = 0;
    int64_t counted = 0;
    for (int64_t i = 0; i < n; ++i)
      if (comp_size[w.component[i]] > 1) {
        scale += val[w.system.diagonal_position(i * pg)];
        ++counted;
      }
    scale = counted ? scale / static_cast<double>(counted) : 1.0;
    for (int64_t i = 0; i < n; ++i) {
      const int32_t c = w.component[i];
      const int dofs = comp_size[c] == 1 ? pg : (comp_first[c] == i ? D : 0);
      for (int a = 0; a < dofs; ++a) w.system.pin(i * pg + a, scale, b);
      // Where the connections form no rigid network (a chain, a tree, a cycle of even length),
      // grains may roll on each other, or turn as gears, with no gap sliding: Xi is singular
      // along such motions, though never inconsistent (the contact forces act through the same
      // connections). A resistance of kRollRegularisation times the grain's largest rotational
      // resistance on each of its rotations holds them at rest and changes the other velocities by
      // about as little. (The largest: a sphere's spin about the line of centres of its only
      // connection has none, and a fraction of it left a pair along an axis singular.)
      if (comp_size[c] > 1) {
        double largest = 0;
        for (int a = 0; a < R; ++a) largest = std::max(largest, val[w.system.diagonal_position(i * pg + D + a)]);
        for (int a = 0; a < R; ++a) val[w.system.diagonal_position(i * pg + D + a)] += kRollRegularisation * largest;
      }
    }
  } else {
    // Inertia or the drag moves a grain alone: none is held.
    record_alone(s, {}, {});
  }

  // Warm start from the last velocities.
  linalg::Vector x(size);
  for (int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) x[i * pg + a] = s.particle_v[D * i + a];
    for (int a = 0; a < R; ++a) x[i * pg + D + a] = s.particle_w[R * i + a];
  }
  for (int k = 0; k < L.n_box; ++k) x[L.box_unknown(k)] = s.box_rate[L.box_axis[k]] / s.box.len[L.box_axis[k]];
  if (!units.identity())
    for (int64_t k = 0; k < size; ++k) x[k] /= units.of(k);

  // The solver, its factor rebuilt from the state's copy after a restore.
  std::vector<double>& stats = s.module_field(f.solver);
  if (stats.size() != kSolverStats) stats.resize(kSolverStats, 0.0);  // a checkpoint of fewer stats: the rest 0
  std::vector<double>& factor = s.module_field(f.factor);
  w.solver.set_settings(p.solver);
  // The held factor is the one the state says (its matrix, how many solves it has served):
  // rebuilt from the state's copy after a restore, or when the state is another than the one the
  // workspace last solved (a replay, the access check's second run), so that a solve depends on
  // the state alone.
  const uint64_t held = factor.empty() ? 0 : field_hash(s, f.factor);
  const bool has_factor = p.solver.method == linalg::Method::kFactorPcg && stats[kFactorAge] >= 0 && !factor.empty() &&
                          static_cast<int64_t>(factor[0]) == size;
  if (!has_factor) {
    w.solver.forget_factor();
  } else if (w.fresh || held != w.factor_hash || !w.solver.factor_valid()) {
    w.solver.restore_factor(load_matrix(factor), static_cast<int>(stats[kFactorAge]));
  } else {
    w.solver.set_solves_since_factor(static_cast<int>(stats[kFactorAge]));
  }
  w.fresh = false;
  const int64_t factorizations_before = w.solver.refactorizations();
  w.solver.on_factor = [&factor](const linalg::SparseMatrix& a) { store_matrix(a, factor); };
  // A factor of the stiff connections alone (gaps below factor_gap) when the others are many,
  // and of each grain's own rotation block only when the rotations are left out of it.
  w.solver.factor_source = nullptr;
  const bool sparser = p.factor_gap_over_a < p.h_max_over_a;
  if (sparser || p.own_rotations)
    w.solver.factor_source = [&w, &cs, &s, &p, sparser]() {
      std::vector<uint8_t> keep(cs.size(), 1);
      for (size_t k = 0; k < cs.size() && sparser; ++k) {
        const Connection& c = cs[k];
        const double dist = std::sqrt(c.r[0] * c.r[0] + c.r[1] * c.r[1] + c.r[2] * c.r[2]);
        keep[k] = dist - s.particle_r[c.i] - s.particle_r[c.j] < p.factor_gap_over_a * p.a;
      }
      return w.system.sparsified(keep, p.own_rotations);
    };
  w.solver.coarse_space = nullptr;
  std::vector<double>& coarse_order = s.module_field(f.coarse_order);
  if (p.coarse_ratio > 0) {
    w.solver.coarse_space = [&cs, &s, &p, &L, units]() {
      linalg::CoarseSpace space = stiff_directions(L, cs, s.particle_r, p.coarse_ratio);
      if (!units.identity())  // the directions of G S, in the unknowns solved for: W's rows scaled in place
        for (int64_t col = 0; col < space.w.outerSize(); ++col)
          for (linalg::SparseMatrix::InnerIterator it(space.w, col); it; ++it) it.valueRef() *= units.of(it.row());
      return space;
    };
    // E ordered from the state's order, so that a solve depends on the state alone.
    linalg::CoarseCorrection::OrderMemory memory;
    if (!coarse_order.empty()) {
      memory.fill = coarse_order[0];
      memory.keys.assign(coarse_order.begin() + 1, coarse_order.end());
    }
    w.solver.set_coarse_order(std::move(memory));
  }
  linalg::SolveReport rep = w.solver.solve(A, b, x, false);
  // The grains' stress to stress_tolerance (a direct solve is refined to round-off already).
  const bool stress_checked = rep.ok() && p.stress_tolerance > 0 && p.solver.method != linalg::Method::kDirect;
  // (none estimated: nan, which reads as no value rather than as exact)
  const double stress_err = stress_checked ? solve_for_stress(m, p, L, cs, s, units, A, b, x, w, rep)
                                           : std::numeric_limits<double>::quiet_NaN();
  w.solver.on_factor = nullptr;
  w.solver.factor_source = nullptr;
  w.solver.coarse_space = nullptr;
  if (p.coarse_ratio > 0) {
    const linalg::CoarseCorrection::OrderMemory& memory = w.solver.coarse().order_memory();
    coarse_order.resize(memory.keys.empty() ? 0 : memory.keys.size() + 1);
    if (!memory.keys.empty()) {
      coarse_order[0] = memory.fill;
      std::copy(memory.keys.begin(), memory.keys.end(), coarse_order.begin() + 1);
    }
  }
  // The stored matrix changes only when the solver factorised (or dropped its factor).
  if (w.solver.refactorizations() != factorizations_before || factor.empty())
    w.factor_hash = factor.empty() ? 0 : field_hash(s, f.factor);
  else w.factor_hash = held;

  stats[kLastIterations] = rep.iterations;
  stats[kLastResidual] = rep.residual;
  stats[kSolves] += 1;
  stats[kIterationsTotal] += rep.iterations;
  stats[kIterationsMax] = std::max<double>(stats[kIterationsMax], rep.iterations);
  stats[kRefactorizations] += static_cast<double>(w.solver.refactorizations() - factorizations_before);
  stats[kFactorAge] = w.solver.factor_valid() ? w.solver.solves_since_factor() : -1;
  stats[kLastStatus] = static_cast<double>(rep.status);
  stats[kConnections] = static_cast<double>(cs.size());
  stats[kCoarseColumns] = static_cast<double>(w.solver.coarse_columns());
  {
    // Said once as it passes the tolerance, and once as it comes back (alone_notice's way): against
    // what the run was last told, which a solve again inside a step leaves to the step's solve
    // after it (its note was lost: the step's found nothing new since).
    const int bits = stress_notice_bits(stats[kStressNotice]);
    const bool was_told_short = (bits & 4) != 0;
    const bool short_now = p.stress_tolerance > 0 && stress_err > p.stress_tolerance;
    // (a check turned off says nothing: its estimate is none)
    const bool changed = short_now != was_told_short && p.stress_tolerance > 0;
    const bool now_told = told ? short_now : was_told_short;
    stats[kStressNotice] = (short_now ? 1 : 0) + (changed ? 2 : 0) + (now_told ? 4 : 0);
    stats[kStressError] = std::isnan(stress_err) ? kNoStressError : stress_err;
  }
  if (!w.solver.factor_valid()) factor.clear();
  if (!rep.ok()) {
    // The value: the residual, or for a matrix not positive definite the unknown where a
    // factorisation (or the diagonal) showed it, -1 where CG met it along a search direction.
    const bool definite = rep.status == linalg::SolveStatus::kNotPositive;
    s.events[at == SolveAt::kAgain ? resolve_event() : solve_event()].raise(
        static_cast<int64_t>(rep.status), definite ? static_cast<double>(rep.column) : rep.residual);
    return;
  }

  if (!units.identity())
    for (int64_t k = 0; k < size; ++k) x[k] *= units.of(k);
  // Each cluster's mean velocity relative to the affine flow is zero (the pinned grain's choice
  // of the translation undone).
  if (pinning) {
    std::vector<double> mean(static_cast<size_t>(n_comp) * D, 0.0);
    for (int64_t i = 0; i < n; ++i)
      for (int a = 0; a < D; ++a) mean[w.component[i] * D + a] += x[i * pg + a];
    for (int64_t i = 0; i < n; ++i) {
      const int32_t c = w.component[i];
      for (int a = 0; a < D; ++a) x[i * pg + a] -= mean[c * D + a] / static_cast<double>(comp_size[c]);
    }
  }
  for (int64_t i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) s.particle_v[D * i + a] = x[i * pg + a];
    for (int a = 0; a < R; ++a) s.particle_w[R * i + a] = x[i * pg + D + a];
  }
  for (int k = 0; k < L.n_box; ++k) s.box_rate[L.box_axis[k]] = x[L.box_unknown(k)] * s.box.len[L.box_axis[k]];

  // The lubrication force of every connection, on i from j, stored at its pair.
  std::vector<double>& f_lub = s.module_field(f.pair_f_lub);
  f_lub.assign(static_cast<size_t>(D * s.n_pairs()), 0.0);
  // And with implicit contacts, their increment over the step: a part of the contact forces the
  // box rows held at the imposed stresses (the stress measured without it missed them).
  std::vector<double>& f_impl = s.module_field(f.pair_f_implicit);
  if (p.implicit_contacts) f_impl.assign(static_cast<size_t>(D * s.n_pairs()), 0.0);
  else f_impl.clear();
  const int nl = local_size(L);
  parallel_for(static_cast<int64_t>(cs.size()), 1024, [&](int64_t lo, int64_t hi) {
    double u[16];
    for (int64_t k = lo; k < hi; ++k) {
      const Connection& c = cs[k];
      for (int q = 0; q < nl; ++q) {
        const int64_t g = local_to_global(L, c, q);
        u[q] = g >= 0 ? x[g] : s.shear_rate;
      }
      const bool stiff = p.implicit_contacts && (c.k_n > 0 || c.k_t > 0);
      connection_force(L, c, s.particle_r[c.i], s.particle_r[c.j], u, &f_lub[D * w.links.pair[k]],
                       stiff ? &f_impl[D * w.links.pair[k]] : nullptr);
    }
  });

  const auto under = solve_parameters(m);
  s.module_field(f.solved_under).assign(under.begin(), under.end());
  const std::vector<double>& forces = s.module_field(dem::forces_under_field());
  s.module_field(f.forces_under).assign(forces.begin(), forces.end());
  // (the first state's solve, and a solve again under steered parameters: its velocities move the
  // grains over this step, bounded as well; a paste_3d_shear restored at 1e-6 times its viscosity,
  // under the same 1 / gammadot, solved its grains 1e6 times faster and overlapped them at once)
  const bool bounded = at != SolveAt::kStep && !p.fixed_dt;
  if (!adapt && !bounded) return;
  if (adapt && step_change > p.dt_change && dt <= p.dt_min)
    s.events[step_event()].raise(kChangeLimit, dt * p.dt_change / step_change);
  // The drift: the velocities just solved move the grains over the next step. (The matrix of an
  // inertial or implicit-contact solve was made with the step before this bound; where it binds,
  // the velocities are those of a slightly longer step, the positions still move by at most this.)
  const double fastest = p.drift_max > 0 ? fastest_rate(s) : 0;  // max |V_i| / r_i
  // (a solve again at a boundary, of a state given or a change while stopped, only shortens the
  // step: a step it cannot take fails as that step, and the change itself is not refused)
  if (fastest * dt_next > p.drift_max && p.drift_max / fastest < p.dt_min && !(at == SolveAt::kAgain && told))
    s.events[step_event()].raise(kDriftLimit, p.drift_max / fastest);
  dt_next = drift_bounded(p, fastest, dt_next);
  // The first solve keeps its step and time scale too: a state saved then and given under a 1e6
  // times larger viscosity took dt_initial of that viscosity, 1e6 times the step its velocities
  // were solved for, and its grains ran into each other at the first step.
  s.module_field(f.dt)[0] = dt_next;
  s.module_field(f.dt_scale)[0] = p.step_scale;
  if (!adapt) s.dt = dt_next;
}

}  // namespace

void lubrication_solve(const Model& m, State& s, PasteWorkspace& w, SolveAt at) { solve_paste(m, s, w, at, true); }

void lubrication_resolve(const Model& m, State& s, PasteWorkspace& w, bool at_boundary) {
  if (!solved_under_other(m, s)) return;
  // An imposed rate enters the solve through the state's rate: impose_shear_rate (a step), or
  // adopt_state (a state given) has set it.
  solve_paste(m, s, w, SolveAt::kAgain, at_boundary);
}

}  // namespace silt::paste
