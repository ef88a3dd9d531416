// The paste module: a scene with [lubrication] is a lubricated granular paste (Peyneau 2009
// sec. 1.5, 2.2, ch. 4-5): grains in a very viscous liquid, interacting by lubrication over
// every gap below h_max and by the DEM's elastic frictional contacts, their velocities solved
// at once every step from one sparse symmetric positive definite system (paste/solve.hpp).
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/machine.hpp"
#include "paste/memory.hpp"
#include "paste/observables.hpp"
#include "paste/params.hpp"
#include "paste/solve.hpp"
#include "paste/stress_accuracy.hpp"
#include "silt/contacts.hpp"
#include "silt/module.hpp"
#include "silt/simulation.hpp"
#include "silt/text.hpp"

namespace silt::paste {
namespace {

// lubrication.coarse_ratio's default in 3D: above a contact's xi_N / xi_T at h_min/a = 1e-4, 1.5e3
// for equal grains, where correcting it cost more than it saved; below that at 1e-5, 1.2e4, where
// it pays. (2D: none.)
constexpr int kCoarseRatio3d = 3000;

std::vector<KeySpec> paste_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  return {
      {"lubrication.viscosity", K::kReal, std::nullopt, Range::positive(), "Pa s", true, {}, "Viscosity eta of the liquid: lubrication xi_N = (3/2) pi eta R^2 / h, xi_T = pi eta R ln(2 R / h) between grains closer than h_max (Peyneau 2009 eq. 1.26-1.29)."},
      {"lubrication.h_min_over_a", K::kReal, Value(1e-2), Range::closed(1e-12, 0.5), "", true, {}, "Roughness cutoff h_min / a, a the largest diameter: below h_min the resistances follow their tangents (or stay constant), in contact they stay at their value at h = 0."},
      {"lubrication.h_max_over_a", K::kReal, Value(0.5), Range::open_closed(0, 2), "", false, {}, "Range h_max / a of the lubrication: grains farther apart are not connected."},
      {"lubrication.cutoff", K::kString, Value(std::string("linear")), Range::any(), "", true, S{"linear", "constant"}, "Below h_min: the tangents at h_min (linear, eq. 1.28-1.29) or the values at h_min (constant, Table 2.3)."},
      {"lubrication.stepper", K::kString, Value(std::string("quasi_static")), Range::any(), "", false, S{"quasi_static", "inertial"}, "quasi_static: Xi V = F (eq. 2.19, no inertia); inertial: (M/dt + Xi) V(t+dt) = M V(t)/dt + F, any Stokes number."},
      {"lubrication.solver", K::kString, Value(std::string("factor_pcg")), Range::any(), "", true, S{"factor_pcg", "cg", "direct"}, "factor_pcg: CG preconditioned by a Cholesky factor of an earlier Xi (CHOLMOD), refactorised when a solve takes more than refactor_iterations; direct: a factorisation every step; cg: Jacobi preconditioner."},
      {"lubrication.tolerance", K::kReal, Value(1e-8), Range::closed(1e-15, 1e-2), "", true, {}, "Relative residual |F - Xi V| / |F| at which CG stops (at least 1e-15: below, round-off in the residual itself)."},
      {"lubrication.stress_tolerance", K::kReal, Value(1e-4), Range::closed(0, 1), "", true, {}, "Relative accuracy of the grains' stress (contacts and lubrication; against its norm, or the imposed pressure or the viscous stress eta gammadot where larger): a solve is taken on past lubrication.tolerance, as far as round-off lets it, while its estimated error (the lubrication stress of the preconditioned residual) exceeds this fraction (with the factor; with solver = cg the estimate is Jacobi's, which can read the error's smooth part low). At small h_min the lubrication multiplies the velocities' error by up to a / h_min: solved to 1e-8 at h_min/a = 1e-12, paste_3d_shear's stress.yy was off by up to 3,000 times its value. 0: the residual's tolerance alone. Observable solver.stress_error."},
      {"lubrication.max_iterations", K::kInt, Value(int64_t{2000}), Range::closed(1, 1e7), "", true, {}, "CG iterations of one solve at most: past them the run stops with a numerical failure."},
      {"lubrication.refactor_iterations", K::kInt, std::nullopt, Range::closed(1, 1e6), "", true, {}, "factor_pcg: a solve that took more iterations has Xi refactorised for the next (default 15 with factor_rotations = whole, 30 with own, whose fresh factor already takes about 20)."},
      {"lubrication.factor_gap_over_a", K::kReal, Value(0.5), Range::non_negative(), "", true, {}, "factor_pcg: connections with a gap below this (in units of a) enter the Cholesky factor whole, the others by their diagonal blocks only: a sparser factor, cheaper to make and to apply, for a few more iterations. h_max / a or more: the whole Xi."},
      {"lubrication.factor_rotations", K::kString, std::nullopt, Range::any(), "", true, S{"whole", "own"}, "factor_pcg (default own in 3D, whole in 2D): whole, the factor is of Xi (or of its stiff connections, factor_gap_over_a); own, of Xi without the couplings of each grain's rotation but its own diagonal block: in 3D a factor a quarter the size, about 4 times cheaper to make, for 2.3 to 3.6 times the CG iterations (the rotations' coupling is then the CG's)."},
      {"lubrication.coarse_ratio", K::kReal, std::nullopt, Range::non_negative(), "", true, {}, "factor_pcg (default " + std::to_string(kCoarseRatio3d) + " in 3D, 0 in 2D, where it was measured not to pay): the directions along which a connection resists more than this many times its tangential lubrication (the normal of a contact at small h_min; with implicit contacts, a sticking contact's tangents too) are solved exactly at each solve beside the factor (a coarse correction), so the factor stays good while those stiff pairs turn as the grains roll. 0: off. A ratio so low that those directions outnumber a quarter of the unknowns (below about 10, most connections' normals) leaves the correction off at that solve: solver.coarse_columns reads 0."},
      {"lubrication.coarse_drop", K::kReal, Value(1e-4), Range::closed(0, 1), "", true, {}, "factor_pcg with coarse_ratio: the couplings of the coarse correction's E = W^T Xi W weaker than this times the geometric mean of their two diagonal entries are moved onto the diagonal (which keeps the preconditioner definite): on a paste's contacts E's factor is then about 3 times smaller for the same iterations. 0: E exact."},
      {"lubrication.factor_precision", K::kString, Value(std::string("single")), Range::any(), "", true, S{"single", "double"}, "factor_pcg: the Cholesky factor applied as the preconditioner with its values rounded to floats (its triangular solves, most of a step's time, read half the bytes; the sums stay in double and the solve's tolerance is the same) or as CHOLMOD made it. A factor with a value a float cannot hold is applied in double."},
      {"lubrication.refactor_every", K::kInt, Value(int64_t{0}), Range::closed(0, 1e9), "", true, {}, "factor_pcg: also refactorise every N solves (0: only on the iteration threshold)."},
      {"lubrication.contacts", K::kString, Value(std::string("explicit")), Range::any(), "", true, S{"explicit", "implicit"}, "explicit: the contact forces of the configuration on the right-hand side (eq. 2.19, the thesis), stable while dt < 2 xi / k for every contact; implicit: also dt times the contacts' stiffnesses in the matrix (normal, and tangential while sticking), a linearised backward Euler with no such limit: the same equilibria, reached in far fewer steps at small h_min."},
      {"lubrication.stokes_drag", K::kBool, Value(false), Range::any(), "", false, {}, "Add a Stokes drag 6 pi eta r on every grain's translation and 8 pi eta r^3 on its rotation (LF_DEM's choice): Xi definite without pinning a grain per cluster. Off: the thesis' model."},
      {"lubrication.dt", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "A fixed time step instead of the adaptive one (the inertial stepper, a convergence study): an alternative to dt_max, dt_initial, dt_min, dt_growth, dt_change and drift_max; at least 1e-12 of the loading's time."},
      {"lubrication.dt_initial", K::kReal, std::nullopt, Range::positive(), "s", false, {}, "First time step (default 1e-3 of the viscous time eta/P, eta a/P in 2D; or 1e-3 / gammadot without a pressure; 1e-3 / gammadot or 1e-3 / w of the cycles where they are faster, Vi > 1; at most dt_max). The inertial stepper's from moving grains is at most sqrt(dt_change) of their fastest viscous relaxation m / xi."},
      {"lubrication.dt_max", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "Largest time step (default 10 viscous times eta/P, eta a/P in 2D; 0.01 / gammadot under shear without a pressure)."},
      {"lubrication.dt_min", K::kReal, std::nullopt, Range::positive(), "s", true, {}, "Smallest time step: an adaptive step that wants less stops the run (default 1e-12 of the time unit)."},
      {"lubrication.dt_growth", K::kReal, Value(1.2), Range::closed(1, 1.5), "", true, {}, "Factor of the time step each step while nothing changes by more than dt_change (sec. 2.2.4: 1.1 to 1.5; 1 keeps it fixed)."},
      {"lubrication.dt_change", K::kReal, Value(0.01), Range::open_closed(0, 1), "", true, {}, "Largest change of a diagonal entry of Xi or of a right-hand side entry in one step, relative to the largest entry (the forces' against the inertial stepper's whole right-hand side M V / dt + F), before the step shrinks."},
      {"lubrication.drift_max", K::kReal, Value(0.05), Range::closed(0, 1), "", true, {}, "Largest displacement of a grain in one adaptive step relative to the affine flow, in units of its radius: the step after a solve is at most drift_max r / |V| for every grain (0: no bound). Xi is near singular where a few grains, held by a chain of connections, can roll on each other; their velocities then jump, which Xi's entries do not show."},
  };
  // clang-format on
}

Cutoff cutoff_of(const std::string& s) { return s == "constant" ? Cutoff::kConstant : Cutoff::kLinear; }

linalg::Method method_of(const std::string& s) {
  if (s == "cg") return linalg::Method::kCg;
  if (s == "direct") return linalg::Method::kDirect;
  return linalg::Method::kFactorPcg;
}

// The values a user may change while a run goes on.
void compile_steerable(const SceneDesc& d, PasteParams& p) {
  p.eta = d.real("lubrication.viscosity");
  p.h_min_over_a = d.real("lubrication.h_min_over_a");
  p.cutoff = cutoff_of(d.string("lubrication.cutoff"));
  p.solver.method = method_of(d.string("lubrication.solver"));
  p.solver.options.tolerance = d.real("lubrication.tolerance");
  p.stress_tolerance = d.real("lubrication.stress_tolerance");
  p.solver.options.max_iterations = static_cast<int>(d.integer("lubrication.max_iterations"));
  p.own_rotations = d.has("lubrication.factor_rotations") ? d.string("lubrication.factor_rotations") == "own"
                                                          : d.integer("scene.dimension") == 3;
  p.solver.refactor_iterations = d.has("lubrication.refactor_iterations")
                                     ? static_cast<int>(d.integer("lubrication.refactor_iterations"))
                                 : p.own_rotations ? 30
                                                   : 15;
  p.solver.refactor_every = static_cast<int>(d.integer("lubrication.refactor_every"));
  p.solver.coarse_drop = d.real("lubrication.coarse_drop");
  p.solver.single_factor = d.string("lubrication.factor_precision") == "single";
  p.factor_gap_over_a = d.real("lubrication.factor_gap_over_a");
  p.coarse_ratio = d.has("lubrication.coarse_ratio")   ? d.real("lubrication.coarse_ratio")
                   : d.integer("scene.dimension") == 3 ? kCoarseRatio3d
                                                       : 0.0;
  p.implicit_contacts = d.string("lubrication.contacts") == "implicit";
  p.dt_growth = d.real("lubrication.dt_growth");
  p.dt_change = d.real("lubrication.dt_change");
  p.drift_max = d.real("lubrication.drift_max");
}

void no_dashpots(ContactParams& c) {
  c.c1 = 0;
  c.zeta = 0;
  c.zeta_t = 0;
}

// The time step: fixed (lubrication.dt), or adaptive from dt_initial within [dt_min, dt_max], in
// units of the viscous time eta a^(3-d) / P (or of the shear time) by default.
void compile_time_step(const SceneDesc& d, const Model& m, PasteParams& p) {
  if (m.box_control.on) p.time_unit = viscous_time(m, p.eta, m.box_control.pressure);
  else if (m.shear.on && m.shear.rate != 0) p.time_unit = 1 / std::abs(m.shear.rate);
  else if (!d.has("lubrication.dt") && (!d.has("lubrication.dt_initial") || !d.has("lubrication.dt_max")))
    d.fail("lubrication.viscosity",
           "without box.pressure or shear.rate there is no time unit: give lubrication.dt, or dt_initial and dt_max");
  if (p.time_unit != 0 && !std::isnormal(p.time_unit))
    // (a pressure of 1e-320 Pa made it infinite, and the first step too long for any bound)
    d.fail(p.time_unit > 1 ? (m.box_control.on ? "box.pressure" : "shear.rate") : "lubrication.viscosity",
           "the paste's time unit (" + std::string(m.box_control.on ? "eta a^(3-d) / P" : "1 / gammadot") + ") is " +
               format_number(p.time_unit, 4) + " s, beyond what double precision resolves");
  // The fastest of the loading's time scales: the viscous time, the shear time, the cycles' 1 / w.
  double scale = p.time_unit;
  if (m.shear.on && m.shear.rate != 0) scale = std::min(scale > 0 ? scale : HUGE_VAL, 1 / std::abs(m.shear.rate));
  if (m.box_control.on && m.box_control.cycle != StressCycle::kNone && m.box_control.cycle_omega > 0)
    scale = std::min(scale > 0 ? scale : HUGE_VAL, 1 / m.box_control.cycle_omega);
  if (d.has("lubrication.dt")) {
    p.fixed_dt = true;
    p.dt_initial = p.dt_min = p.dt_max = d.real("lubrication.dt");
    // The adaptive step's floor, the same for a fixed step (1e-15 of the viscous time was taken
    // without a word; a run of any length was then steps that moved nothing).
    if (scale > 0 && p.dt_initial < 1e-12 * scale)
      d.fail("lubrication.dt", "the time step " + format_number(p.dt_initial, 4) +
                                   " s is below 1e-12 of the loading's time (" + format_number(scale, 4) +
                                   " s), the adaptive step's smallest by default");
    if (p.time_unit == 0) p.time_unit = p.dt_initial;
    return;
  }
  const double unit = p.time_unit;
  p.step_scale = scale;
  p.dt_max = d.has("lubrication.dt_max") ? d.real("lubrication.dt_max") : (m.box_control.on ? 10 : 0.01) * unit;
  // The first step: 1e-3 of the time unit, and of the shear time 1 / gammadot or the cycles' 1 / w
  // where they are the faster (Vi > 1 under a pressure: 1e-3 of the viscous time would shear the grains by
  // Vi / 1000 in the first step, a whole strain at Vi = 1e3, whose grains then passed through each
  // other); within dt_max.
  double first = 1e-3 * unit;
  if (m.shear.on && m.shear.rate != 0) first = std::min(first, 1e-3 / std::abs(m.shear.rate));
  if (m.box_control.on && m.box_control.cycle != StressCycle::kNone && m.box_control.cycle_omega > 0)
    first = std::min(first, 1e-3 / m.box_control.cycle_omega);
  p.dt_initial = d.has("lubrication.dt_initial") ? d.real("lubrication.dt_initial") : std::min(first, p.dt_max);
  // (of the fastest time scale: under a shear much faster than the viscous time, Vi >> 1, the
  // default dt_min of the viscous time exceeded the first step)
  p.dt_min = d.has("lubrication.dt_min") ? d.real("lubrication.dt_min")
                                         : 1e-12 * (p.step_scale > 0 ? p.step_scale : p.dt_initial);
  if (p.dt_min > p.dt_initial || p.dt_initial > p.dt_max) {
    // At the key given (a default's bound broken by another key's value), with the three values.
    const std::string at =
        d.first_given({"lubrication.dt_initial", "lubrication.dt_max", "lubrication.dt_min"}, "lubrication.dt_initial");
    d.fail(at, "the time steps must satisfy dt_min <= dt_initial <= dt_max: here dt_min = " +
                   format_number(p.dt_min, 4) + ", dt_initial = " + format_number(p.dt_initial, 4) +
                   ", dt_max = " + format_number(p.dt_max, 4) + " (those not given are defaults)");
  }
}

void compile_paste(const SceneDesc& d, Model& m) {
  PasteParams& p = m.params.get<PasteParams>();
  const std::string key = "lubrication.viscosity";
  if (!m.walls.empty()) d.fail(key, "a paste is periodic: walls are not supported with [lubrication]");
  if (m.n_frozen > 0) d.fail(key, "a paste cannot hold frozen grains (every grain's velocity is solved)");
  if (m.gravity.norm() > 0)
    d.fail(d.first_given({"gravity.vector", "gravity.magnitude", "gravity.angle"}, key),
           "a paste has no gravity (its grains are neutrally buoyant); remove [gravity]");
  // The paste solves for the box's strain rates at imposed stresses, and for the grains under an
  // imposed shear rate (or viscous number): a shear stress imposed was accepted and the paste
  // stood still (its solve took the rate as given, and 0).
  if (m.shear.on && m.shear.stress_controlled)
    d.fail("shear.stress",
           "a paste is sheared at an imposed viscous number (shear.viscous_number) or rate "
           "(shear.rate); an imposed shear stress is not solved for");
  if (m.module_on("drag")) d.fail(key, "[drag] and [lubrication] both act on the grains; use lubrication.stokes_drag");
  compile_steerable(d, p);
  p.h_max_over_a = d.real("lubrication.h_max_over_a");
  if (p.h_max_over_a <= p.h_min_over_a)
    d.fail("lubrication.h_max_over_a", "h_max / a must exceed h_min / a = " + format_number(p.h_min_over_a));
  p.a = m.a_max;
  p.stepper = d.string("lubrication.stepper") == "inertial" ? Stepper::kInertial : Stepper::kQuasiStatic;
  p.stokes_drag = d.boolean("lubrication.stokes_drag");
  compile_time_step(d, m, p);
  m.dt_key = p.fixed_dt ? "lubrication.dt" : "lubrication.dt_max";
  m.dt_text = (p.fixed_dt ? "fixed time step " : "adaptive time step: the first ") + format_number(p.dt_initial, 5) +
              m.unit("s");
  m.drift_key = p.fixed_dt || p.drift_max <= 0 ? "" : "lubrication.drift_max";
  // The DEM's part: contacts without dashpots (the liquid dissipates; the dry ones are kept for
  // the preparation), pairs listed out to h_max, grains never renumbered (the stored factor
  // follows the unknowns' numbering).
  p.dry_contact = m.contact;
  p.dry_pair_contact = m.pair_contact;
  no_dashpots(m.contact);
  for (ContactParams& c : m.pair_contact) no_dashpots(c);
  const double h_max = p.h_max_over_a * p.a;
  m.pair_gap = h_max;
  if (!d.has("neighbor.skin")) m.skin = h_max + 0.1 * m.a_max;
  if (m.skin <= h_max)
    d.fail("neighbor.skin", "the skin must exceed the lubrication range h_max = " + format_number(h_max) + " m");
  if (!d.has("neighbor.contact_skin")) m.contact_skin = 0.2 * m.skin;
  for (int k = 0; k < m.dim; ++k)
    if (m.box.periodic[k] && m.box.len[k] < 2 * m.interaction_range())
      d.fail(key, "the periodic box is shorter than twice the lubrication reach 2 r_max + skin = " +
                      format_number(m.interaction_range()));
  m.sort_grains = false;
  m.velocities_solved = true;
  m.adaptive_dt = true;
  m.pair_forces_every_step = true;
  m.pair_stress_fields.push_back(paste_fields().pair_f_lub);
  m.pair_stress_fields.push_back(paste_fields().pair_f_implicit);  // (empty with explicit contacts)
  m.kinetic_stress = p.stepper == Stepper::kInertial;
}

double paste_memory_bytes(const Model& m) { return m.params.get<PasteParams>().memory.total(); }

std::string megabytes(double bytes) { return format_number(bytes / (1 << 20), 3) + " MiB"; }

void finish_paste(const SceneDesc& d, Model& m) {
  PasteParams& p = m.params.get<PasteParams>();
  p.memory = estimate_paste_memory(m);
  const PasteMemory& e = p.memory;
  const double need = estimated_memory_bytes(m), have = available_memory_bytes();
  if (need > 0.9 * have)
    d.fail("lubrication.viscosity",
           "the paste needs about " + format_number(need / (1 << 30), 3) + " GiB, of which the Cholesky factor of Xi " +
               format_number(e.factor / (1 << 30), 3) + " GiB (" + std::to_string(e.connections) +
               " connections at Phi = " + format_number(e.phi, 3) + ", " + std::to_string(e.entries) +
               " entries in Xi); the machine has " + format_number(have / (1 << 30), 3) +
               " GiB available: use fewer grains, a smaller lubrication.h_max_over_a, or lubrication.solver = \"cg\" "
               "(no factor)");
}

std::string describe_paste(const Model& m) {
  const PasteParams& p = m.params.get<PasteParams>();
  std::ostringstream o;
  o.precision(5);
  o << "paste        lubrication eta = " << p.eta << m.unit("Pa s") << ", h_min/a = " << p.h_min_over_a
    << ", h_max/a = " << p.h_max_over_a << ", " << (p.cutoff == Cutoff::kLinear ? "linear" : "constant")
    << " cutoff (Peyneau 2009 eq. 1.28-1.29); " << stepper_name(p.stepper) << " stepper, "
    << linalg::method_name(p.solver.method) << " solver to " << p.solver.options.tolerance
    << (p.solver.method == linalg::Method::kFactorPcg && p.own_rotations
            ? ", its factor of the translations (each grain's rotation by its own block)"
            : std::string())
    << (p.solver.method == linalg::Method::kFactorPcg && p.coarse_ratio > 0
            ? ", its factor corrected on the directions stiffer than " + format_number(p.coarse_ratio) + " xi_T"
            : std::string())
    << (p.stokes_drag ? ", Stokes drag on every grain" : ", one grain pinned per cluster") << "; "
    << (p.implicit_contacts ? "implicit contacts ((Xi + dt K) V = F)" : "explicit contacts (eq. 2.19)") << "\n";
  const bool pressure = m.box_control.on;
  const double rate = m.shear.on && !m.shear.stress_controlled ? std::abs(m.shear.rate) : 0.0;
  // The time unit compile_time_step chose: the viscous time, else the shear time 1 / |gammadot|.
  const char* unit =
      pressure ? (m.dim == 2 ? "eta a/P" : "eta/P") : (m.shear.on && m.shear.rate != 0 ? "1/gammadot" : nullptr);
  if (p.fixed_dt) o << "             time step fixed at " << p.dt_initial << m.unit("s") << "\n";
  else {
    o << "             time step adaptive (sec. 2.2.4) from " << p.dt_initial << m.unit("s") << ", in [" << p.dt_min
      << ", " << p.dt_max << "]" << m.unit("s");
    if (unit) o << "; time unit " << unit << " = " << p.time_unit << m.unit("s");
    if (p.drift_max > 0) o << "; a grain moves at most " << p.drift_max << " of its radius a step";
    o << "\n";
  }
  // The dimensionless groups: kappa against the stress that drives the grains (the imposed
  // pressure, else the viscous stress eta gammadot of an imposed rate), Vi against the pressure
  // (Peyneau eq. 1.34, 4.1, 5.7), and the Stokes number St = m gammadot / (eta a) of a grain of
  // diameter a at the loading's rate (whether the inertial stepper's mass matters).
  auto stokes = [&](double r) { return m.m_a * r / (p.eta * p.a); };
  const char* vi = m.dim == 2 ? "Vi = eta gammadot a / P = " : "Vi = eta gammadot / P = ";
  if (pressure) {
    const double P = m.box_control.pressure;
    o << "             kappa = " << stiffness_number_text(m, P) << "; ";
    if (rate > 0) {
      o << vi << viscous_number(m, p.eta, rate, P) << "; St = m gammadot / (eta a) = " << stokes(rate);
    } else if (m.box_control.cycle != StressCycle::kNone) {
      const double w = m.box_control.cycle_omega;
      o << "cycles Vi = eta w" << (m.dim == 2 ? " a" : "") << " / P = " << viscous_number(m, p.eta, w, P)
        << "; St = m w / (eta a) = " << stokes(w);
    } else if (m.shear.stress_controlled) {
      o << "imposed shear stress: Vi is measured (observable Vi); St at the time unit tau = m / (eta a tau) = "
        << stokes(1 / p.time_unit);
    } else {
      o << "St at the time unit tau = m / (eta a tau) = " << stokes(1 / p.time_unit);
    }
    o << "\n";
  } else if (rate > 0) {
    const double viscous = viscous_stress(m, p.eta, rate);
    o << "             kappa at the viscous stress eta gammadot = " << stiffness_number_text(m, viscous)
      << "; St = m gammadot / (eta a) = " << stokes(rate) << " (no imposed pressure: no Vi)\n";
  }
  const PasteMemory& e = p.memory;
  o << "             memory beyond the grains about " << megabytes(e.total()) << ": the Cholesky factor "
    << megabytes(e.factor) << " (CHOLMOD's analysis of " << e.connections
    << " connections, the initial grains at Phi = " << e.phi << "), Xi (" << e.entries
    << " entries), its buffers and copies " << megabytes(e.held) << ", a step's peak " << megabytes(e.transient)
    << "\n";
  return o.str();
}

// The DEM's step and the box's mass act in the dry preparation only: a paste solves its step and
// its box's strain rates with the grains' velocities (run.dt set in a running paste replied "from
// the next step" and changed nothing).
std::string inert_in_paste(const Model& m, const std::string& key) {
  if (!m.velocities_solved) return "";
  if (key == "run.dt" || key == "run.dt_over_tc")
    return key + " sets the step of the dry preparation only: the paste's is lubrication.dt, or its adaptive keys";
  if (key == "box.mass_factor")
    return "box.mass_factor acts in the dry preparation only: the paste solves its box's strain rates with the "
           "grains' velocities";
  return "";
}

std::string steer_paste(Model& m, const Model& fresh) {
  PasteParams& p = m.params.get<PasteParams>();
  const PasteParams& f = fresh.params.get<PasteParams>();
  if (f.stepper != p.stepper || f.stokes_drag != p.stokes_drag || f.h_max_over_a != p.h_max_over_a)
    return "the stepper, the drag and h_max change the system solved: set them when stopped";
  const double unit = p.time_unit;
  p = PasteParams(f);
  p.time_unit = unit;
  m.dt_key = fresh.dt_key;  // a fixed step set or unset: the key an overlap's report names
  m.drift_key = fresh.drift_key;
  m.dt_text = fresh.dt_text;
  return "";
}

// A stored count or index: a whole number from lo to hi (false for NaN).
bool whole_in(double v, double lo, double hi) { return v >= lo && v <= hi && v == std::floor(v); }

std::string check_paste_state(const Model& m, const State& s) {
  const PasteFields f = paste_fields();
  const auto& stats = s.module_field(f.solver);
  // A checkpoint written before the stress's error was kept holds two stats fewer, one written
  // before the coarse correction three.
  if (!stats.empty() && stats.size() != kSolverStats && stats.size() != kStressError && stats.size() != kCoarseColumns)
    return "paste_solver has the wrong length";
  // The solves the held factor has served, the solver's int (-1: none held).
  if (!stats.empty() && !whole_in(stats[kFactorAge], -1, std::numeric_limits<int>::max()))
    return "paste_solver's factor age is not a whole number of solves";
  const auto& dt = s.module_field(f.dt);
  if (dt.size() != 1 || !(dt[0] >= 0)) return "paste_dt is not a time step";
  if (const size_t k = s.module_field(f.pair_f_implicit).size();
      k != 0 && k != static_cast<size_t>(m.dim * s.n_pairs()))
    return "pair_f_implicit has the wrong length";
  const int64_t size = make_layout(m, s.n).size();
  // (The change watched and the stored factor of other unknowns, a checkpoint of a box under
  // pressure restored into a fixed one: dropped when the state is adopted, paste_adopt.)
  const auto& alone = s.module_field(f.alone);
  if (!alone.empty()) {
    if (alone[0] != 0 && alone[0] != 1) return "paste_alone's flag is neither 0 nor 1";
    for (size_t k = 1; k < alone.size(); ++k)
      if (!whole_in(alone[k], 0, static_cast<double>(s.n) - 1) || (k > 1 && !(alone[k] > alone[k - 1])))
        return "paste_alone's grain ids are out of range or out of order";
  }
  const auto& order = s.module_field(f.coarse_order);
  if (!order.empty()) {
    if (!(order[0] >= 0 && order[0] < 1e12)) return "paste_coarse_order's fill-in is not a ratio";
    for (size_t k = 1; k < order.size(); ++k)
      if (!whole_in(order[k], 0, 0x1p53 - 1)) return "paste_coarse_order's keys are not whole numbers in range";
  }
  const auto& a = s.module_field(f.factor);
  if (a.empty() || a[0] != static_cast<double>(size)) return "";
  if (a.size() < 2 || !whole_in(a[1], 0, 1e12) || a.size() != static_cast<size_t>(2 + (size + 1) + 2 * a[1]))
    return "paste_factor is not a matrix of the paste's unknowns";
  const auto nnz = static_cast<int64_t>(a[1]);
  const double* col = a.data() + 2;
  const double* row = col + size + 1;
  if (col[0] != 0 || col[size] != static_cast<double>(nnz)) return "paste_factor's columns do not span its entries";
  // Every column start bounded before any is used as an index (a start far past the entries,
  // then smaller ones, would be read first).
  for (int64_t k = 0; k < size; ++k)
    if (!whole_in(col[k + 1], col[k], col[size]))
      return "paste_factor's column starts decrease or are not whole numbers";
  for (int64_t k = 0; k < size; ++k) {
    for (auto p = static_cast<int64_t>(col[k]); p < static_cast<int64_t>(col[k + 1]); ++p)
      if (!whole_in(row[p], 0, static_cast<double>(size) - 1) || (p > col[k] && !(row[p] > row[p - 1])))
        return "paste_factor's rows are out of range or out of order";
  }
  return "";
}

// A state given to a paste of other unknowns (a box's lengths controlled in one and fixed in the
// other) keeps its velocities but not the change its adaptive step watched nor its stored factor:
// both are made again at the next solve.
void paste_adopt(const Model& m, State& s) {
  const PasteFields f = paste_fields();
  const int64_t size = make_layout(m, s.n).size();
  auto& change = s.module_field(f.change);
  if (!change.empty() && static_cast<int64_t>(change.size()) != 2 * size) change.clear();
  auto& factor = s.module_field(f.factor);
  if (!factor.empty() && factor[0] != static_cast<double>(size)) factor.clear();
}

void paste_to_dry(Model& c) {
  const PasteParams& p = c.params.get<PasteParams>();
  c.contact = p.dry_contact;
  c.pair_contact = p.dry_pair_contact;
  std::erase(c.modules, std::string("paste"));
  c.velocities_solved = false;
  c.adaptive_dt = false;
  // The DEM's step (a failure of the compression advised lowering lubrication.dt_max, which the
  // dry compression does not use).
  c.dt_key = "run.dt";
  c.dt_text.clear();
  c.pair_gap = 0;
  c.pair_stress_fields.clear();
  c.kinetic_stress = true;
}

}  // namespace

const ModuleSpec& module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "paste";
    s.doc = "lubricated granular paste: lubrication and contacts, every velocity from one implicit solve";
    s.keys = paste_keys();
    mark_initial(s.keys, {"lubrication.dt_initial"});
    for (KeySpec& k : s.keys)
      if (k.path == "lubrication.coarse_ratio")
        k.computed = [](const Model& m) {
          // (without the paste there is none: `params` on a dry scene failed on the missing block)
          return m.module_on("paste") ? format_number(m.params.get<PasteParams>().coarse_ratio) : std::string();
        };
    s.fields = {
        {"pair_f_lub", Extent::kPairVec, "N",
         "lubrication force on i from j (eq. 2.24), 0 beyond h_max; lubrication_solve"},
        {"paste_dt", Extent::kScalar, "s", "adaptive time step of the next step (sec. 2.2.4); lubrication_solve"},
        {"paste_dt_scale", Extent::kScalar, "s",
         "the time scale paste_dt was chosen under (PasteParams::step_scale; 0 before the first step): a steered "
         "viscosity, pressure or rate that lowers it cuts the step by the new scale over it; lubrication_solve"},
        {"paste_solved_under", Extent::kFree, "",
         "the parameters the velocities were solved under (viscosity, h_min / a, h_max / a, cutoff, Stokes drag, "
         "implicit contacts, pressure, cycle amplitude and w, shear rate and stress): others in the model solve them "
         "again before the step moves the grains (lubrication_resolve); lubrication_solve"},
        {"paste_forces_under", Extent::kFree, "",
         "dem_forces_under as the velocities were solved: the contact forces made again since under other "
         "parameters (a friction steered) solve them again before the step moves the grains; lubrication_solve"},
        {"paste_solver", Extent::kFree, "", "solver counts (paste/solve.hpp SolverStat); lubrication_solve"},
        {"pair_f_implicit", Extent::kFree, "N",
         "with implicit contacts (else empty), the increment dt K G V of each contact's force over the step, on i "
         "from j, which the solve counted with the contact forces; lubrication_solve"},
        {"paste_change", Extent::kFree, "",
         "Xi's diagonal and the right-hand side of the last solve, for the adaptive step; lubrication_solve"},
        {"paste_factor", Extent::kFree, "",
         "the matrix the held Cholesky factor was made from (n, nnz, columns, rows, values): a restart refactorises "
         "it; lubrication_solve"},
        {"paste_coarse_order", Extent::kFree, "",
         "the coarse correction's order (linalg CoarseCorrection::OrderMemory): the fill-in of its last fresh "
         "ordering, then its columns' keys, 3 (i n + j) + d for the direction d (0 the normal, 1 and 2 the "
         "tangents) of the connection of grains i < j, in the elimination order of its last factor, from which "
         "the next is ordered; lubrication_solve"},
        {"paste_alone", Extent::kFree, "",
         "1 when the set changed at the last solve (else 0), then the ids of the grains with no lubricated "
         "connection, held at the affine flow, in increasing order; lubrication_solve"}};
    s.events = {"paste_resolve", "paste_solve", "paste_step"};  // (in order of precedence: the resolve runs first)
    s.observables = paste_observables();
    s.enabled = [](const SceneDesc& d) { return d.has("lubrication.viscosity"); };
    s.needs_grains = true;
    s.compile = compile_paste;
    s.finish = finish_paste;
    s.memory_bytes = paste_memory_bytes;
    s.describe = describe_paste;
    s.steer = steer_paste;
    s.inert = inert_in_paste;
    s.check_state = check_paste_state;
    s.notice = [](const Model& m, const State& st) {
      std::string alone = alone_notice(st), stress = stress_notice(m, st);
      return alone.empty() || stress.empty() ? alone + stress : alone + "; " + stress;
    };
    s.summary_group = "solver";
    s.summary_counts = {"solves", "iters_max", "refactorisations", "connections", "coarse_columns"};
    s.summary = [](const Model&, const State& st) -> std::vector<std::pair<std::string, double>> {
      const auto& v = st.module_field(paste_fields().solver);
      if (v.size() != kSolverStats) return {};
      const double solves = v[kSolves];
      return {{"solves", solves},
              {"iters_mean", solves > 0 ? v[kIterationsTotal] / solves : 0.0},
              {"iters_max", v[kIterationsMax]},
              {"refactorisations", v[kRefactorizations]},
              {"last_residual", v[kLastResidual]},
              {"stress_error", stress_error_of(v[kStressError])},
              {"connections", v[kConnections]},
              {"coarse_columns", v[kCoarseColumns]}};
    };
    // A fixed step or the adaptive step's keys (dt_growth, dt_change and drift_max were taken beside
    // a fixed step and did nothing); the shell's `set` of one replaces the other.
    s.rules = {KeyRule::one_of({{"lubrication.dt"},
                                {"lubrication.dt_max", "lubrication.dt_initial", "lubrication.dt_min",
                                 "lubrication.dt_growth", "lubrication.dt_change", "lubrication.drift_max"}})};
    s.prepare_dry = paste_to_dry;
    // No solve yet: a packing compressed dry (prepare.compress, or one given by --restore), whose
    // velocities and box rates are the compression's. The first drift needs the paste's own.
    s.adopt = paste_adopt;
    s.unstarted = [](const Model&, const State& st) {
      const auto& v = st.module_field(paste_fields().solver);
      // (an older checkpoint may hold fewer stats)
      return v.size() <= kSolves || v[kSolves] == 0;
    };
    // Its velocities solved under other parameters: solved again (lubrication_resolve), with the
    // contact forces it holds (the setup's would stretch the tangential springs a second time).
    s.stale = [](const Model& m, const State& st) { return solved_under_other(m, st); };
    return s;
  }();
  return spec;
}

}  // namespace silt::paste
