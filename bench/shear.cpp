// Rheology of dry frictionless spheres in simple shear at imposed pressure (Peyneau 2009 ch. 3,
// scenes/shear3d_frictionless.toml): mu* and Phi against the inertial number, with the
// block-averaging error of the mean, next to the thesis' values; then the numerical knobs (time
// step as a fraction of the contact time, box mass, neighbour skin) against cost.
//
//   build/bench/shear [--threads N] [--low] [--quick] [--2d] [--only KNOB] [--inertial LIST]
//                     [--mass F] [--dt F] [--scene FILE] [--set KEY=VALUE ...]
//
// --2d runs scenes/shear2d_dry.toml instead (Peyneau ch. 4 dry disks, mu = 0.3 and 0) at
// I = 0.1 and 1e-2 next to the thesis' fits (Tables 4.1 and 4.3).
//
// One isotropic compression (procedure O) gives the packing every run starts from. A run shears
// through a transient strain, then averages over a measured strain, sampled every 0.005 of
// strain. Two estimators of the friction: mu* = <tau>/<sigma_yy> (ratio of the means), with the
// error of a ratio of correlated means (the block-averaging error of the series
// tau - mu* sigma_yy, divided by <sigma_yy>: the delta method with the covariance; the error
// that treats the two means as independent is kept for comparison), and Peyneau's eq. 3.14,
// <|sigma_xy| / sigma_yy> (the `mu` observable, block-averaged). Also z, z* = z/(1 - p0), the
// mechanical skeleton's z_mech and the connectivity p_n (fraction of grains with n contacts,
// Peyneau Table 3.14).
//
// --low adds I = 1e-2 and 3.16e-3 (with --2d: 1e-3); --inertial 0.1,0.01 chooses the values (2D
// too); --mass F gives the I cases a box of mass F N m (a light box settles faster after the
// start from rest, and a start at I > 0.5 needs one), --dt F a time step of F t_c (2D too);
// --only I|dt|dt_probe|mass|skin|2d0.3|2d0 runs one group; --quick divides every strain by 4 (a
// smoke test, not a measurement).
//
// The time-step cases (dt, dt_probe) start from a steady flow at I = 3.16e-2: the prepared
// packing sheared through the transient at 0.05 t_c. "dt" compiles each time step as a user
// would: silt refuses a step beyond the velocity-Verlet limit of one contact at the largest
// allowed overlap (limits.max_overlap), so a step above 0.05 t_c runs with the largest overlap
// that the compile check accepts, and stops if a contact goes beyond it. "dt_probe" (0.1 and
// 0.2 t_c) lifts that bound: the model is compiled at 0.05 t_c and its step then set to the
// probed one, so the run stops only on what the integration does (an overlap beyond the
// scene's 2 %, runaway energy, a non-finite value).
// Appends to bench/results/shear.csv.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "bench_util.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "silt/simulation.hpp"

using namespace silt;

namespace {

struct Args {
  int threads = 2;
  bool low = false;
  bool two_d = false;
  std::string only;              // run only the cases of this knob (I, dt, mass, skin)
  double mass_factor = 1;        // box mass / (N m) of the I cases (--mass)
  double dt_over_tc = 0.05;      // time step of the I cases (--dt)
  std::vector<double> inertial;  // --inertial: replaces the list of I
  double strain_scale = 1;
  std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/shear3d_frictionless.toml";
  std::vector<std::string> sets;
};

struct Case {
  std::string knob;  // "I", "dt", "dt_probe", "mass", "skin", "2d0.3", "2d0"
  double inertial = 0, dt_over_tc = 0.05, mass_factor = 1, skin = 0.1;
  double transient = 0, measured = 0;  // strains
  double friction = -1;                // < 0: the scene's
  double thesis_mu = 0, thesis_phi = 0;
  bool from_steady = false;    // start from the steady flow at I = 3.16e-2 instead of the packing
  bool lift_dt_bound = false;  // compile at 0.05 t_c, then run at dt_over_tc (dt_probe)
};

constexpr int kMaxContacts = 10;  // p_n recorded for n = 0 .. 10 (Peyneau's Table 3.14)

struct Result {
  bool ok = true;
  std::string failure;
  BlockAverage mu, mu314, phi, syy, z, z_star, z_mech, ke;
  double mu_err_independent = 0;
  std::array<double, kMaxContacts + 1> pn{};
  double dt = 0, steps = 0, wall = 0, profile_dev = 0, strain_reached = 0;
};

Model model_for(const Args& a, const Case& c) {
  std::vector<Override> o;
  for (const std::string& s : a.sets) o.push_back(parse_override(s));
  auto add = [](std::vector<Override>& list, const char* key, double v) {
    std::ostringstream s;
    s.precision(17);
    s << key << "=" << v;
    list.push_back(parse_override(s.str()));
  };
  add(o, "shear.inertial_number", c.inertial);
  add(o, "box.mass_factor", c.mass_factor);
  add(o, "neighbor.skin", c.skin);
  if (c.friction >= 0) add(o, "contact.friction", c.friction);
  std::vector<Override> at_005 = o;
  add(at_005, "run.dt_over_tc", std::min(c.dt_over_tc, 0.05));
  Model ref = compile(load_scene_file(a.scene, at_005));
  if (c.dt_over_tc <= 0.05) return ref;
  // Steps above 0.05 t_c. The compile check bounds dt by the velocity-Verlet limit of one
  // contact at the largest allowed overlap h_max; the Hertz stiffness grows as h^(1/2), so that
  // limit goes as h_max^(-1/4): the largest h_max it accepts for this dt is h_max times
  // (limit / dt)^4, from the same scene at 0.05 t_c.
  const double dt = c.dt_over_tc * ref.t_contact;
  if (c.lift_dt_bound) {
    ref.dt = dt;
    return ref;
  }
  add(o, "run.dt_over_tc", c.dt_over_tc);
  if (dt > ref.dt_stable && ref.contact.law == NormalLaw::kHertz)  // the linear laws' limit is fixed
    add(o, "limits.max_overlap", 0.999 * ref.limits.max_overlap * std::pow(ref.dt_stable / dt, 4));
  return compile(load_scene_file(a.scene, o));
}

Result shear(const Args& a, const Case& c, const State& start) {
  Result r;
  Simulation sim(model_for(a, c), a.threads);
  const Model& m = sim.model();
  sim.restore(start);
  const double gd = m.shear.rate, strain0 = sim.state().shear_strain;
  r.dt = m.dt;
  const int64_t transient = static_cast<int64_t>(c.transient / (gd * m.dt));
  const int64_t measured = static_cast<int64_t>(c.measured / (gd * m.dt));
  const int64_t every = std::max<int64_t>(1, static_cast<int64_t>(0.005 / (gd * m.dt)));  // every 0.005 strain
  RunOptions warm;
  warm.steps = transient;
  RunReport rep = sim.run(warm);
  double wall = rep.wall_s, steps = static_cast<double>(rep.steps_done);
  std::vector<double> tau, syy, ratio, phi, z, z_star, z_mech, ke;
  std::array<double, kMaxContacts + 1> pn_sum{};
  const int slabs = std::max(4, static_cast<int>(sim.state().box.len[1] / m.a_max));
  std::vector<double> prof(slabs, 0.0);
  int64_t nprof = 0;
  RunOptions run;
  run.steps = measured;
  run.hooks.push_back({every, [&](const State& s) {
                         const Measurements q = measure(m, s);
                         tau.push_back(-q.stress[0][1]);
                         syy.push_back(q.stress[1][1]);
                         ratio.push_back(std::abs(q.stress[0][1]) / q.stress[1][1]);  // the `mu` observable
                         phi.push_back(q.phi);
                         z.push_back(q.z);
                         z_star.push_back(q.z_star);
                         z_mech.push_back(q.z_mech);
                         for (size_t n = 0; n < q.pn.size() && n <= kMaxContacts; ++n) pn_sum[n] += q.pn[n];
                         ke.push_back(q.ke_fluct / (m.m_a * m.a_max * m.a_max * gd * gd));
                         const VelocityProfile p = velocity_profile(m, s, slabs);
                         for (int k = 0; k < slabs; ++k) prof[k] += p.vx[k] / (gd * s.box.len[1]);
                         ++nprof;
                       }});
  if (rep.end != RunEnd::kFailed) {
    rep = sim.run(run);
    wall += rep.wall_s;
    steps += static_cast<double>(rep.steps_done);
  }
  r.strain_reached = sim.state().shear_strain - strain0;
  if (rep.end == RunEnd::kFailed) {
    r.ok = false;
    r.failure = sim.state().failure.message;
  }
  r.wall = wall;
  r.steps = steps;
  if (tau.empty()) return r;  // failed in the transient: nothing measured
  // mu* = <tau> / <sigma_yy>. Its error (delta method): mu* - mu_true ~ <tau - mu* sigma_yy> /
  // <sigma_yy>, so the block-averaging error of that series over <sigma_yy> holds the
  // covariance of the two means, which the independent propagation leaves out.
  const BlockAverage bt = block_average(tau);
  r.syy = block_average(syy);
  r.mu.mean = bt.mean / r.syy.mean;
  r.mu.n = bt.n;
  std::vector<double> u(tau.size());
  for (size_t k = 0; k < tau.size(); ++k) u[k] = tau[k] - r.mu.mean * syy[k];
  r.mu.err = block_average(u).err / r.syy.mean;
  r.mu_err_independent = std::abs(r.mu.mean) * std::hypot(bt.err / bt.mean, r.syy.err / r.syy.mean);
  r.mu314 = block_average(ratio);
  r.phi = block_average(phi);
  r.z = block_average(z);
  r.z_star = block_average(z_star);
  r.z_mech = block_average(z_mech);
  for (int n = 0; n <= kMaxContacts; ++n) r.pn[n] = pn_sum[n] / static_cast<double>(nprof);
  r.ke = block_average(ke);
  for (int k = 0; k < slabs; ++k)  // largest deviation of the mean profile from the affine one
    r.profile_dev = std::max(r.profile_dev, std::abs(prof[k] / static_cast<double>(nprof) - (k + 0.5) / slabs));
  return r;
}

int run(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) a.threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--low")) a.low = true;
    else if (!std::strcmp(argv[i], "--quick")) a.strain_scale = 0.25;
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) a.only = argv[++i];
    else if (!std::strcmp(argv[i], "--inertial") && i + 1 < argc) a.inertial = bench::parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--2d")) {
      a.two_d = true;
      a.scene = std::string(SILT_SOURCE_DIR) + "/scenes/shear2d_dry.toml";
    } else if (!std::strcmp(argv[i], "--scene") && i + 1 < argc) a.scene = argv[++i];
    else if (!std::strcmp(argv[i], "--mass") && i + 1 < argc) a.mass_factor = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--dt") && i + 1 < argc) a.dt_over_tc = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--set") && i + 1 < argc) a.sets.push_back(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: shear [--threads N] [--low] [--quick] [--2d] [--only KNOB] [--inertial LIST] [--mass F] "
                   "[--dt F] [--scene FILE] [--set KEY=VALUE ...]\n");
      return 1;
    }
  }
  // Peyneau (2009) Table 3.3 (N = 4000, kappa_1, zeta = 0.98, M = N m).
  // I = 3.16e-3: Table 3.6 at N = 1372. I = 5.6e-1 ... 5.6e-4: Table 3.5 (kappa_1, N = 4000; mu*
  // only, Phi 0 for "not given").
  const std::map<double, std::pair<double, double>> thesis = {
      {0.316, {0.415, 0.566}}, {0.0316, {0.212, 0.620}}, {0.00316, {0.1457, 0.6322}}, {0.56, {0.5031, 0}},
      {0.056, {0.2435, 0}},    {0.0056, {0.1571, 0}},    {0.00056, {0.1250, 0}}};

  std::vector<Case> cases;
  std::vector<double> inertial = {0.316, 0.1, 0.0316};
  if (a.low) inertial.insert(inertial.end(), {0.01, 0.00316});
  if (!a.inertial.empty()) inertial = a.inertial;
  if (a.two_d) {
    std::vector<double> values = {0.1, 0.01};
    if (a.low) values.push_back(1e-3);
    if (!a.inertial.empty()) values = a.inertial;
    inertial.clear();
    for (double mu : {0.3, 0.0})
      for (double I : values) {
        Case c;
        c.knob = mu > 0 ? "2d0.3" : "2d0";
        c.inertial = I;
        c.friction = mu;
        c.dt_over_tc = a.dt_over_tc;
        c.transient = I > 0.05 ? 3 : 2;
        c.measured = I > 0.05 ? 20 : (I > 0.005 ? 6 : 3);
        // Fits of Peyneau's Tables 4.1 and 4.3: mu* = mu0 + c I^alpha, 1/Phi = 1/Phi0 + e I^nu.
        c.thesis_mu = mu > 0 ? 0.208 + 0.79 * std::pow(I, 0.81) : 0.094 + 0.54 * std::pow(I, 0.52);
        c.thesis_phi = 1.0 / (mu > 0 ? 1 / 0.8228 + 0.356 * std::pow(I, 0.87) : 1 / 0.8416 + 0.213 * std::pow(I, 0.67));
        cases.push_back(c);
      }
  }
  for (double I : inertial) {
    Case c;
    c.knob = "I";
    c.inertial = I;
    c.mass_factor = a.mass_factor;
    c.dt_over_tc = a.dt_over_tc;
    // The box (M = N m) settles slowly after the start from rest at large I: long transients.
    c.transient = I > 0.2 ? 40 : (I > 0.05 ? 10 : (I > 0.02 ? 3 : (I > 0.005 ? 2 : 1)));
    c.measured = I > 0.2 ? 120 : (I > 0.05 ? 40 : (I > 0.02 ? 15 : (I > 0.005 ? 6 : 4)));
    cases.push_back(c);
  }
  // One knob away from a base case, the others at their defaults.
  auto sweep = [&](const char* knob, Case from, std::initializer_list<double> values, double Case::*field) {
    if (a.two_d) return;
    from.knob = knob;
    for (double value : values) {
      Case c = from;
      c.*field = value;
      cases.push_back(c);
    }
  };
  Case at_003;
  at_003.inertial = 0.0316;
  at_003.transient = 3;
  at_003.measured = 15;
  Case steady_003 = at_003;  // from the steady flow: a short transient for the new step
  steady_003.from_steady = true;
  steady_003.transient = 0.5;
  sweep("dt", steady_003, {0.02, 0.035, 0.05, 0.07, 0.1, 0.2}, &Case::dt_over_tc);
  steady_003.lift_dt_bound = true;
  sweep("dt_probe", steady_003, {0.1, 0.2}, &Case::dt_over_tc);
  Case at_03;
  at_03.inertial = 0.316;
  at_03.transient = 40;
  at_03.measured = 120;
  sweep("mass", at_03, {1e-3, 1e-2, 10.0}, &Case::mass_factor);  // 1 is the I = 0.316 row above
  Case short_003 = at_003;
  short_003.transient = 0.5;
  short_003.measured = 2;
  sweep("skin", short_003, {0.05, 0.1, 0.2, 0.4}, &Case::skin);  // cost only: the physics does not depend on it

  std::vector<std::string> knobs;
  for (const Case& c : cases)
    if (std::find(knobs.begin(), knobs.end(), c.knob) == knobs.end()) knobs.push_back(c.knob);
  bench::check_only(a.only, knobs);

  // Procedure O, once.
  Case base;
  base.inertial = 0.0316;
  Model m0 = model_for(a, base);
  PreparationReport prep;
  const double t0 = bench::now_s();
  const State prepared = prepare_packing(m0, a.threads, &prep);
  const double phi_iso = measure(m0, prepared).phi;
  std::printf("procedure O: N = %lld, Phi_iso = %.4f after %lld steps (%.1f s)%s\n",
              static_cast<long long>(m0.n_grains), phi_iso, static_cast<long long>(prep.steps), bench::now_s() - t0,
              prep.end == RunEnd::kStatic ? ", static" : ", NOT static");

  // The steady flow the time-step cases start from: the packing sheared at I = 3.16e-2 and
  // 0.05 t_c through the transient.
  State steady;
  for (const Case& c : cases)
    if (c.from_steady && (a.only.empty() || c.knob == a.only)) {
      Case warm = at_003;
      warm.measured = 0;
      Simulation sim(model_for(a, warm), a.threads);
      sim.restore(prepared);
      RunOptions opt;
      opt.steps = static_cast<int64_t>(warm.transient * a.strain_scale / (sim.model().shear.rate * sim.model().dt));
      if (sim.run(opt).end == RunEnd::kFailed) throw std::runtime_error("steady flow: " + sim.state().failure.message);
      steady = sim.state();
      std::printf("steady flow for the time-step cases: I = %g, strain %.2f at dt = 0.05 t_c\n", warm.inertial,
                  steady.shear_strain);
      break;
    }

  std::printf("\n%-8s %-8s %-6s %-6s %-5s %-17s %-17s %-17s %-17s %-16s %-6s %-6s %-6s %-6s %-7s %-8s %-8s %-11s %s\n",
              "knob", "I", "dt/tc", "M/Nm", "skin", "mu* +- err", "(indep. err)", "<|sxy|/syy>", "Phi +- err",
              "syy/P-1 +- err", "z", "z*", "z_mech", "p0", "profile", "s/strain", "Mstep/s", "thesis", "status");
  const std::string csv = std::string(SILT_SOURCE_DIR) + "/bench/results/shear.csv";
  for (Case c : cases) {
    if (!a.only.empty() && c.knob != a.only) continue;
    c.transient *= a.strain_scale;
    c.measured *= a.strain_scale;
    const Result r = shear(a, c, c.from_steady ? steady : prepared);
    auto th = thesis.count(c.inertial) && !a.two_d ? thesis.at(c.inertial) : std::pair{0.0, 0.0};
    if (c.thesis_mu > 0) th = {c.thesis_mu, c.thesis_phi};
    char mu[40], indep[40], mu314[40], phi[40], syy[40], ref[40];
    std::snprintf(mu, sizeof mu, "%.4f +- %.4f", r.mu.mean, r.mu.err);
    std::snprintf(indep, sizeof indep, "(+- %.4f)", r.mu_err_independent);
    std::snprintf(mu314, sizeof mu314, "%.4f +- %.4f", r.mu314.mean, r.mu314.err);
    std::snprintf(phi, sizeof phi, "%.4f +- %.4f", r.phi.mean, r.phi.err);
    std::snprintf(syy, sizeof syy, "%+.4f +- %.4f", r.syy.mean - 1, r.syy.err);
    if (th.first > 0 && th.second > 0) std::snprintf(ref, sizeof ref, "%.3f/%.3f", th.first, th.second);
    else if (th.first > 0) std::snprintf(ref, sizeof ref, "%.4f/-", th.first);
    else std::snprintf(ref, sizeof ref, "-");
    const double strain = r.strain_reached;
    const double psps = r.wall > 0 ? m0.n_grains * r.steps / r.wall : 0;
    const std::string status =
        r.ok ? "ok" : "failed after a strain of " + std::to_string(strain).substr(0, 6) + ": " + r.failure;
    std::printf(
        "%-8s %-8.4g %-6.3g %-6.0e %-5.3g %-17s %-17s %-17s %-17s %-16s %-6.3f %-6.3f %-6.3f %-6.4f %-7.4f %-8.3f "
        "%-8.3f %-11s %s\n",
        c.knob.c_str(), c.inertial, c.dt_over_tc, c.mass_factor, c.skin, mu, indep, mu314, phi, syy, r.z.mean,
        r.z_star.mean, r.z_mech.mean, r.pn[0], r.profile_dev, strain > 0 ? r.wall / strain : 0, psps / 1e6, ref,
        status.c_str());
    std::fflush(stdout);
    std::string failure = r.failure;  // one CSV field
    for (char& ch : failure)
      if (ch == ',' || ch == '\n') ch = ';';
    std::ostringstream row;
    row.precision(6);
    row << bench::today() << "," << m0.n_grains << "," << a.threads << "," << c.knob << "," << c.inertial << ","
        << c.dt_over_tc << "," << c.mass_factor << "," << c.skin << "," << c.transient << "," << c.measured << ","
        << r.mu.mean << "," << r.mu_err_independent << "," << r.phi.mean << "," << r.phi.err << "," << r.syy.mean << ","
        << r.syy.err << "," << r.z.mean << "," << r.ke.mean << "," << r.profile_dev << ","
        << (strain > 0 ? r.wall / strain : 0) << "," << psps << "," << th.first << "," << th.second << ","
        << (r.ok ? "ok" : "failed") << "," << phi_iso << "," << r.mu.err << "," << r.mu314.mean << "," << r.mu314.err
        << "," << r.z_star.mean << "," << r.z_mech.mean;
    for (int n = 0; n <= kMaxContacts; ++n) row << "," << r.pn[n];
    std::string sets;  // the --set overrides, one field
    for (const std::string& o : a.sets) sets += (sets.empty() ? "" : ";") + o;
    row << "," << (c.from_steady ? "steady" : "packing") << "," << strain << "," << failure << "," << sets;
    std::string header =
        "date,n,threads,knob,I,dt_over_tc,mass_factor,skin,transient_strain,measured_strain,mu,mu_err,phi,phi_err,"
        "syy_over_p,syy_err,z,ke_fluct_over_ma2gd2,profile_dev,wall_per_strain,particle_steps_per_s,thesis_mu,"
        "thesis_phi,status,phi_iso,mu_err_cov,mu_eq314,mu_eq314_err,z_star,z_mech";
    for (int n = 0; n <= kMaxContacts; ++n) header += ",p" + std::to_string(n);
    header += ",start,strain_reached,failure,overrides";
    bench::append_csv(csv, header, row.str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
