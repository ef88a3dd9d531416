// The paste's stages (paste/solve.hpp). In a step:
//
//   choose_dt -> paste_dt -> lubrication_resolve -> (box_drift ->) drift -> update_neighbors
//                                                -> contact_forces -> lubrication_solve
//
// and for the first state, lubrication_solve after the DEM's sum_forces: the velocities the first
// drift moves the grains with.
#include <cmath>
#include <string>

#include "dem/forces_under.hpp"
#include "graph/adders.hpp"
#include "paste/lubrication_laws.hpp"
#include "paste/solve.hpp"
#include "shear/cycle_origin.hpp"
#include "silt/text.hpp"

namespace silt::graph {
namespace {

Access solve_reads() {
  const paste::PasteFields f = paste::paste_fields();
  return {fid::t,
          fid::dt,
          fid::particle_x,
          fid::particle_r,
          fid::particle_v,
          fid::particle_w,
          fid::particle_f,
          fid::particle_t,
          fid::particle_inv_m,
          fid::particle_inv_i,
          fid::nbr_start,
          fid::pair_j,
          fid::pair_f,
          fid::pair_hist,       // implicit contacts: which springs stick
          fid::particle_group,  // implicit contacts: the pair's contact law
          fid::box,
          fid::box_rate,
          fid::shear_rate,
          f.pair_f_lub,
          f.dt,
          f.solver,
          f.change,
          f.factor,
          f.alone,
          f.coarse_order,
          f.dt_scale,
          f.solved_under,
          f.pair_f_implicit,
          f.forces_under,
          dem::forces_under_field(),    // the parameters of the contact forces solved with
          shear::cycle_origin_field(),  // the cycles' phase, for the imposed stresses
          fid::particle_id};            // names the grains alone
}

Access solve_writes() {
  const paste::PasteFields f = paste::paste_fields();
  return {fid::particle_v, fid::particle_w, fid::box_rate,     f.pair_f_lub,  f.dt,
          f.solver,        f.change,        f.factor,          f.alone,       f.coarse_order,
          f.dt_scale,      f.solved_under,  f.pair_f_implicit, f.forces_under};
}

// And the state's step: the first solve's (which the state shows before it), or one the drift
// bound shortens after a solve again under changed parameters.
Access solve_and_step_writes() {
  Access a = solve_writes();
  a.push_back(fid::dt);
  return a;
}

void diagnose_paste(GraphBuilder& b) {
  // A failed solve, in the step's solve or in the one again under changed parameters.
  for (const auto& solve : {std::pair{paste::solve_event(), "lubrication_solve"},
                            std::pair{paste::resolve_event(), "lubrication_resolve"}}) {
    const char* stage = solve.second;
    b.diagnose(solve.first, [stage](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
      const auto& p = m.params.get<paste::PasteParams>();
      const auto& stats = s.module_field(paste::paste_fields().solver);
      const auto status = static_cast<linalg::SolveStatus>(e.first());
      const double iters = stats.size() == paste::kSolverStats ? stats[paste::kLastIterations] : 0;
      f.stage = stage;
      // A direct solve past the tolerance, or CG whose true residual stayed above it (kStagnated):
      // below 1e-4, the round-off of an ill-conditioned Xi (the solution is near, the tolerance the
      // knob); above, a nearly singular Xi solved inaccurately.
      auto residual_left = [&](const std::string& what) {
        const bool round_off = e.value() < 1e-4;
        f.parameter = round_off ? "lubrication.tolerance" : "lubrication.h_max_over_a";
        f.message =
            what + format_number(e.value(), 4) +
            ", above lubrication.tolerance = " + format_number(p.solver.options.tolerance, 4) +
            (round_off
                 ? std::string(p.solver.method == linalg::Method::kDirect ? ": refining the solve does not lower it"
                                                                          : ": more iterations do not lower it") +
                       ", the round-off of so ill-conditioned a Xi "
                       "(h_min/a = " +
                       format_number(p.h_min_over_a, 4) + "); raise lubrication.tolerance or lubrication.h_min_over_a"
                 : ": Xi is numerically singular (something moves with almost no lubricated "
                   "gap resisting it); compress the grains first (prepare.compress), raise "
                   "lubrication.h_max_over_a, or set lubrication.stokes_drag = true");
      };
      switch (status) {
        case linalg::SolveStatus::kMaxIterations: {
          if (p.solver.method == linalg::Method::kDirect) {
            residual_left("the direct lubrication solve left a relative residual of ");
            break;
          }
          // The iteration limit came first. A residual that reached round-off (1e-12 and below)
          // stalled there: the tolerance is the knob.
          const bool stalled = e.value() < 1e-12;
          f.parameter = stalled ? "lubrication.tolerance" : "lubrication.max_iterations";
          f.message = "the lubrication solve did not converge: relative residual " + format_number(e.value(), 4) +
                      " after " + format_number(iters, 4) +
                      " iterations (lubrication.max_iterations = " + format_number(p.solver.options.max_iterations, 4) +
                      "), above lubrication.tolerance = " + format_number(p.solver.options.tolerance, 4) +
                      (stalled ? "; the residual stalls at round-off there: raise lubrication.tolerance"
                               : "; raise lubrication.max_iterations, or use lubrication.solver = \"direct\"");
          break;
        }
        case linalg::SolveStatus::kStagnated:
          residual_left("the lubrication solve stalled after " + format_number(iters, 4) +
                        " iterations at a relative residual of ");
          break;
        case linalg::SolveStatus::kNotPositive: {
          // Which unknown: a grain's (by its id) or a box length's.
          const int pg = m.dim == 2 ? 3 : 6;
          const auto col = static_cast<int64_t>(e.value());
          const bool at_unknown = col >= 0 && col < s.n * pg + m.dim;
          if (at_unknown && col >= s.n * pg) {
            f.parameter = "box.pressure";
            f.message =
                "no lubricated gap resists the box's pressure (Xi is singular at a box strain rate): the "
                "grains are too far apart for h_max; compress them first (prepare.compress) or raise "
                "lubrication.h_max_over_a";
            break;
          }
          if (at_unknown) f.particle = s.particle_id[col / pg];
          const std::string where = at_unknown ? " at grain " + std::to_string(f.particle) : std::string();
          // With the drag on, nothing moves free: the resistances overflowed, or span more than
          // double precision holds (a viscosity of 1e300 with the drag on was told to set it).
          if (p.stokes_drag) {
            const double xi_top = paste::xi_normal(p.h_min_over_a * p.a, p.a / 2, p.law());
            f.parameter = "lubrication.h_min_over_a";
            f.message = "the resistance matrix is not positive definite" + where +
                        " although every grain has its Stokes drag: its resistances, up to " +
                        (std::isfinite(xi_top) ? format_number(xi_top, 3) : std::string("more than 1e308")) +
                        " N s/m at h_min (lubrication.viscosity = " + format_number(p.eta, 4) +
                        " Pa s), are beyond what double precision resolves; raise lubrication.h_min_over_a or "
                        "bring the viscosity nearer the loads' scale";
            break;
          }
          f.parameter = "lubrication.stokes_drag";
          f.message = "the resistance matrix is not positive definite" + where +
                      ": something moves without any lubricated gap changing; set lubrication.stokes_drag = true";
          break;
        }
        default: {
          // The loads by name and value: a viscous number of 1e200 overflowed with "lower the loads".
          std::string loads;
          if (m.shear.on && !m.shear.stress_controlled)
            loads += "the shear rate " + format_number(m.shear.rate, 4) + " 1/s";
          if (m.shear.on && m.shear.stress_controlled)
            loads += "the shear stress " + format_number(m.shear.stress, 4) + " Pa";
          if (m.box_control.on)
            loads += (loads.empty() ? "" : ", ") + std::string("the pressure ") +
                     format_number(m.box_control.pressure, 4) + " Pa";
          // The largest resistance, xi_N at h_min between two grains of diameter a (R_eq = a / 2):
          // past 1e300 Xi's sums overflow, whatever the loads (a viscosity of 1e306 was told to
          // lower them).
          const double xi_top = paste::xi_normal(p.h_min_over_a * p.a, p.a / 2, p.law());
          if (!(xi_top < 1e300)) {
            f.parameter = "lubrication.viscosity";
            f.message = "the lubrication resistances overflow: at h_min they reach " +
                        (std::isfinite(xi_top) ? format_number(xi_top, 3) : std::string("more than 1e308")) +
                        " N s/m (lubrication.viscosity = " + format_number(p.eta, 4) +
                        " Pa s); lower the viscosity or raise lubrication.h_min_over_a";
            break;
          }
          f.parameter = "lubrication.h_min_over_a";
          f.message = "the lubrication solve met a non-finite value (residual " + format_number(e.value(), 4) +
                      "): the forces or the resistances overflowed; raise lubrication.h_min_over_a or lower the loads" +
                      (loads.empty() ? "" : " (" + loads + ")");
        }
      }
    });
  }
  b.diagnose(paste::mass_event(), [](const Model&, const State&, const EventSlot& e, StepFailure& f) {
    f.stage = "lubrication_solve";
    f.particle = e.first();
    f.parameter = "lubrication.stepper";
    f.message = "grain " + std::to_string(e.first()) + "'s m / dt is " + format_number(e.value(), 3) +
                " of the largest resistance of Xi: the inertial stepper cannot resolve the grains' common "
                "translations, which only the masses "
                "resist, in double precision; at so small a Stokes number use lubrication.stepper = "
                "\"quasi_static\" (this limit), or lubrication.stokes_drag = true";
  });
  b.diagnose(paste::step_event(), [](const Model& m, const State& s, const EventSlot& e, StepFailure& f) {
    const auto& p = m.params.get<paste::PasteParams>();
    f.stage = "lubrication_solve";
    f.parameter = "lubrication.dt_min";
    const bool drift = e.first() == paste::kDriftLimit;  // else the change of Xi or the forces
    f.message = "the adaptive time step wants " + format_number(e.value(), 4) +
                " s, below lubrication.dt_min = " + format_number(p.dt_min, 4) + " s (step " + std::to_string(s.step) +
                (drift ? "): a grain moves too fast for lubrication.drift_max = " + format_number(p.drift_max, 4) +
                             " of its radius a step; lower lubrication.dt_min, raise lubrication.drift_max, or "
                             "lubrication.stokes_drag = true (a drag on every grain bounds its velocity)"
                       : "): the configuration changes too fast for the explicit positions (an entry of Xi or "
                         "of the forces by more than lubrication.dt_change = " +
                             format_number(p.dt_change, 4) +
                             " of the largest in one step); lower lubrication.dt_min, raise lubrication.dt_change, "
                             "or raise lubrication.h_min_over_a (stiffer lubrication at contact)");
  });
}

}  // namespace

void add_paste_stages(GraphBuilder& b) {
  auto& w = b.workspaces().get<paste::PasteWorkspace>();
  if (b.phase() == Phase::kSetup) {
    const int solve = b.add(
        "lubrication_solve",
        [&w](const Model& m, State& s) { paste::lubrication_solve(m, s, w, paste::SolveAt::kFirst); }, solve_reads(),
        solve_and_step_writes());
    b.after(solve, b.find("sum_forces"), "solves with the contact forces of the first state");
    b.after(solve, b.find("restore_springs"), "implicit contacts: the springs as the first step starts them");
    b.after(solve, b.find("record_forces_under"), "keeps the parameters of the contact forces it solved with");
    if (const int rate = b.find("impose_shear_rate"); rate >= 0)
      b.after(solve, rate, "solves under the imposed rate as the model has it now");
    diagnose_paste(b);
    return;
  }
  const paste::PasteFields f = paste::paste_fields();
  // (a state before its first step: its first step from its velocities, as the first solve's)
  const int dt = b.add("paste_dt", &paste::paste_dt,
                       {fid::dt, fid::step, fid::particle_v, fid::particle_r, f.dt, f.dt_scale}, {fid::dt});
  b.light(dt);
  if (const int choose = b.find("choose_dt"); choose >= 0)
    b.after(dt, choose, "replaces the DEM's step by the paste's (lubrication.dt, or the adaptive one)");
  const bool given = b.phase() == Phase::kResolve;  // (its notes said at once, not after a step)
  const int again = b.add(
      "lubrication_resolve", [&w, given](const Model& m, State& s) { paste::lubrication_resolve(m, s, w, given); },
      solve_reads(), solve_and_step_writes());
  b.after(again, dt, "solves with this step's dt");
  if (const int rate = b.find("impose_shear_rate"); rate >= 0)
    b.after(again, rate, "solves under the imposed rate as the model has it now");
  // A state given under changed parameters: its step, and its velocities solved again (and no more).
  if (b.phase() == Phase::kResolve) {
    b.after(dt, b.find("restore_springs"), "the contact forces made again stretched the springs by the last step");
    b.after(again, b.find("sum_forces"), "solves with the contact forces, made again if they were stale");
    b.after(again, b.find("record_forces_under"), "keeps the parameters of the contact forces it solves with");
    diagnose_paste(b);
    return;
  }
  const int origin = b.find("cycle_origin");
  if (origin >= 0) b.after(again, origin, "imposes the stresses of the cycles' phase under this step's w");
  b.after(b.find("drift"), again, "moves the grains by this step's dt and velocities");
  if (const int box = b.find("box_drift"); box >= 0) b.after(box, again, "moves the box by this step's dt and rates");
  const int solve = b.add(
      "lubrication_solve", [&w](const Model& m, State& s) { paste::lubrication_solve(m, s, w, paste::SolveAt::kStep); },
      solve_reads(), solve_writes());
  b.after(solve, b.find("contact_forces"), "solves with this step's contact forces");
  if (origin >= 0) b.after(solve, origin, "imposes the stresses of the cycles' phase under this step's w");
  diagnose_paste(b);
}

}  // namespace silt::graph
