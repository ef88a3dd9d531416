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
// through a transient strain, then averages over a measured strain; mu* = <tau>/<sigma_yy>.
// --low adds I = 1e-2 and 3.16e-3 (with --2d: 1e-3); --inertial 0.1,0.01 chooses the values;
// --mass F gives the I cases a box of mass F N m (a light box settles faster after the start
// from rest, and a start at I > 0.5 needs one), --dt F a time step of F t_c; --only
// I|dt|mass|skin runs one group; --quick divides every strain by 4 (a smoke test, not a
// measurement).
// Appends to bench/results/shear.csv.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>
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
  std::string only;  // run only the cases of this knob (I, dt, mass, skin)
  double mass_factor = 1;  // box mass / (N m) of the I cases (--mass)
  double dt_over_tc = 0.05;  // time step of the I cases (--dt)
  std::vector<double> inertial;  // --inertial: replaces the list of I
  double strain_scale = 1;
  std::string scene = std::string(SILT_SOURCE_DIR) + "/scenes/shear3d_frictionless.toml";
  std::vector<std::string> sets;
};

struct Case {
  std::string knob;  // "I", "dt", "mass", "skin"
  double inertial = 0, dt_over_tc = 0.05, mass_factor = 1, skin = 0.1;
  double transient = 0, measured = 0;  // strains
  double friction = -1;                // < 0: the scene's
  double thesis_mu = 0, thesis_phi = 0;
};

struct Result {
  bool ok = true;
  std::string failure;
  BlockAverage mu, phi, syy, z, ke;
  double dt = 0, steps = 0, wall = 0, profile_dev = 0;
};

Model model_for(const Args& a, const Case& c) {
  std::vector<Override> o;
  for (const std::string& s : a.sets) o.push_back(parse_override(s));
  auto add = [&](const char* key, double v) {
    std::ostringstream s;
    s.precision(17);
    s << key << "=" << v;
    o.push_back(parse_override(s.str()));
  };
  add("shear.inertial_number", c.inertial);
  add("run.dt_over_tc", c.dt_over_tc);
  add("box.mass_factor", c.mass_factor);
  add("neighbor.skin", c.skin);
  if (c.friction >= 0) add("contact.friction", c.friction);
  // Large steps need a stability bound at a smaller largest overlap; a run that exceeds it stops.
  if (c.dt_over_tc > 0.05) add("limits.max_overlap", 0.02 * std::pow(0.05 / c.dt_over_tc, 4) * 0.8);
  return compile(load_scene_file(a.scene, o));
}

Result shear(const Args& a, const Case& c, const State& prepared) {
  Result r;
  Simulation sim(model_for(a, c), a.threads);
  const Model& m = sim.model();
  sim.restore(prepared);
  const double gd = m.shear.rate;
  r.dt = m.dt;
  const int64_t transient = static_cast<int64_t>(c.transient / (gd * m.dt));
  const int64_t measured = static_cast<int64_t>(c.measured / (gd * m.dt));
  const int64_t every = std::max<int64_t>(1, static_cast<int64_t>(0.005 / (gd * m.dt)));  // every 0.005 strain
  RunOptions warm;
  warm.steps = transient;
  RunReport rep = sim.run(warm);
  double wall = rep.wall_s, steps = static_cast<double>(rep.steps_done);
  std::vector<double> mu, tau, syy, phi, z, ke;
  const int slabs = std::max(4, static_cast<int>(sim.state().box.len[1] / m.a_max));
  std::vector<double> prof(slabs, 0.0);
  int64_t nprof = 0;
  RunOptions run;
  run.steps = measured;
  run.hooks.push_back({every, [&](const State& s) {
                         const Measurements q = measure(m, s);
                         tau.push_back(-q.stress[0][1]);
                         syy.push_back(q.stress[1][1]);
                         phi.push_back(q.phi);
                         z.push_back(q.z);
                         ke.push_back(q.ke_fluct / (m.m_mean * m.a_max * m.a_max * gd * gd));
                         const VelocityProfile p = velocity_profile(m, s, slabs);
                         for (int k = 0; k < slabs; ++k) prof[k] += p.vx[k] / (gd * s.box.len[1]);
                         ++nprof;
                       }});
  if (rep.end != RunEnd::kFailed) {
    rep = sim.run(run);
    wall += rep.wall_s;
    steps += static_cast<double>(rep.steps_done);
  }
  if (rep.end == RunEnd::kFailed) {
    r.ok = false;
    r.failure = "failed: " + sim.state().failure.message.substr(0, 70);
  }
  // mu* = <tau> / <sigma_yy>, its error by propagation of the two block-averaging errors.
  const BlockAverage bt = block_average(tau);
  r.syy = block_average(syy);
  r.mu.mean = r.syy.mean != 0 ? bt.mean / r.syy.mean : 0;
  r.mu.err = std::abs(r.mu.mean) * std::hypot(bt.err / bt.mean, r.syy.err / r.syy.mean);
  r.mu.n = bt.n;
  r.phi = block_average(phi);
  r.z = block_average(z);
  r.ke = block_average(ke);
  for (int k = 0; k < slabs; ++k)  // largest deviation of the mean profile from the affine one
    r.profile_dev = std::max(r.profile_dev, std::abs(prof[k] / std::max<int64_t>(1, nprof) - (k + 0.5) / slabs));
  r.wall = wall;
  r.steps = steps;
  return r;
}

int run(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) a.threads = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--low")) a.low = true;
    else if (!std::strcmp(argv[i], "--quick")) a.strain_scale = 0.25;
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) a.only = argv[++i];
    else if (!std::strcmp(argv[i], "--inertial") && i + 1 < argc) {
      std::istringstream in(argv[++i]);
      std::string item;
      while (std::getline(in, item, ',')) a.inertial.push_back(std::stod(item));
    }
    else if (!std::strcmp(argv[i], "--2d")) {
      a.two_d = true;
      a.scene = std::string(SILT_SOURCE_DIR) + "/scenes/shear2d_dry.toml";
    }
    else if (!std::strcmp(argv[i], "--scene") && i + 1 < argc) a.scene = argv[++i];
    else if (!std::strcmp(argv[i], "--mass") && i + 1 < argc) a.mass_factor = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--dt") && i + 1 < argc) a.dt_over_tc = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--set") && i + 1 < argc) a.sets.push_back(argv[++i]);
    else {
      std::fprintf(stderr, "usage: shear [--threads N] [--low] [--quick] [--2d] [--only KNOB] [--inertial LIST] [--mass F] [--dt F] [--scene FILE] [--set KEY=VALUE ...]\n");
      return 1;
    }
  }
  // Peyneau (2009) Table 3.3 (N = 4000, kappa_1, zeta = 0.98, M = N m).
  // I = 3.16e-3: Table 3.6 at N = 1372. I = 5.6e-1 ... 5.6e-4: Table 3.5 (kappa_1, N = 4000; mu*
  // only, Phi 0 for "not given").
  const std::map<double, std::pair<double, double>> thesis = {
      {0.316, {0.415, 0.566}}, {0.0316, {0.212, 0.620}}, {0.00316, {0.1457, 0.6322}}, {0.56, {0.5031, 0}},
      {0.056, {0.2435, 0}},    {0.0056, {0.1571, 0}},    {0.00056, {0.1250, 0}}};

  // Procedure O, once.
  Case base;
  base.inertial = 0.0316;
  Model m0 = model_for(a, base);
  PreparationReport prep;
  const double t0 = bench::now_s();
  const State prepared = prepare_packing(m0, a.threads, &prep);
  const double phi_iso = measure(m0, prepared).phi;
  std::printf("procedure O: N = %lld, Phi_iso = %.4f after %lld steps (%.1f s)%s\n", static_cast<long long>(m0.n_grains),
              phi_iso, static_cast<long long>(prep.steps), bench::now_s() - t0,
              prep.end == RunEnd::kStatic ? ", static" : ", NOT static");

  std::vector<Case> cases;
  std::vector<double> inertial = {0.316, 0.1, 0.0316};
  if (a.low) inertial.insert(inertial.end(), {0.01, 0.00316});
  if (!a.inertial.empty()) inertial = a.inertial;
  if (a.two_d) {
    inertial.clear();
    std::vector<double> values = {0.1, 0.01};
    if (a.low) values.push_back(1e-3);
    for (double mu : {0.3, 0.0})
      for (double I : values) {
        Case c;
        c.knob = mu > 0 ? "2d0.3" : "2d0";
        c.inertial = I;
        c.friction = mu;
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
  sweep("dt", at_003, {0.02, 0.035, 0.05, 0.07, 0.1, 0.2}, &Case::dt_over_tc);
  Case at_03;
  at_03.inertial = 0.316;
  at_03.transient = 40;
  at_03.measured = 120;
  sweep("mass", at_03, {1e-3, 1e-2, 10.0}, &Case::mass_factor);  // 1 is the I = 0.316 row above
  Case short_003 = at_003;
  short_003.transient = 0.5;
  short_003.measured = 2;
  sweep("skin", short_003, {0.05, 0.1, 0.2, 0.4}, &Case::skin);  // cost only: the physics does not depend on it

  std::printf("\n%-5s %-8s %-7s %-6s %-6s %-18s %-18s %-15s %-7s %-7s %-9s %-9s %-9s %s\n", "knob", "I", "dt/tc", "M/Nm",
              "skin", "mu* +- err", "Phi +- err", "syy/P-1 +- err", "z", "profile", "wall/strain", "Mstep/s", "thesis",
              "status");
  const std::string csv = std::string(SILT_SOURCE_DIR) + "/bench/results/shear.csv";
  for (Case c : cases) {
    if (!a.only.empty() && c.knob != a.only) continue;
    c.transient *= a.strain_scale;
    c.measured *= a.strain_scale;
    const Result r = shear(a, c, prepared);
    auto th = thesis.count(c.inertial) && !a.two_d ? thesis.at(c.inertial) : std::pair{0.0, 0.0};
    if (c.thesis_mu > 0) th = {c.thesis_mu, c.thesis_phi};
    char mu[40], phi[40], syy[40], ref[40];
    std::snprintf(mu, sizeof mu, "%.4f +- %.4f", r.mu.mean, r.mu.err);
    std::snprintf(phi, sizeof phi, "%.4f +- %.4f", r.phi.mean, r.phi.err);
    std::snprintf(syy, sizeof syy, "%+.4f +- %.4f", r.syy.mean - 1, r.syy.err);
    if (!r.ok) {
      std::snprintf(mu, sizeof mu, "-");
      std::snprintf(phi, sizeof phi, "-");
      std::snprintf(syy, sizeof syy, "-");
    }
    if (th.first > 0 && th.second > 0) std::snprintf(ref, sizeof ref, "%.3f/%.3f", th.first, th.second);
    else if (th.first > 0) std::snprintf(ref, sizeof ref, "%.4f/-", th.first);
    else std::snprintf(ref, sizeof ref, "-");
    const double strain = c.transient + c.measured;
    const double psps = r.wall > 0 ? m0.n_grains * r.steps / r.wall : 0;
    std::printf("%-5s %-8.4g %-7.3g %-6.0e %-6.3g %-18s %-18s %-15s %-7.3f %-7.4f %-9.3f %-9.3f %-9s %s\n", c.knob.c_str(),
                c.inertial, c.dt_over_tc, c.mass_factor, c.skin, mu, phi, syy, r.z.mean, r.profile_dev, r.wall / strain,
                psps / 1e6, ref, r.ok ? "ok" : r.failure.c_str());
    std::fflush(stdout);
    std::ostringstream row;
    row.precision(6);
    row << bench::today() << "," << m0.n_grains << "," << a.threads << "," << c.knob << "," << c.inertial << ","
        << c.dt_over_tc << "," << c.mass_factor << "," << c.skin << "," << c.transient << "," << c.measured << ","
        << r.mu.mean << "," << r.mu.err << "," << r.phi.mean << "," << r.phi.err << "," << r.syy.mean << "," << r.syy.err
        << "," << r.z.mean << "," << r.ke.mean << "," << r.profile_dev << "," << r.wall / strain << "," << psps << ","
        << th.first << "," << th.second << "," << (r.ok ? "ok" : "failed") << "," << phi_iso;
    bench::append_csv(csv,
                      "date,n,threads,knob,I,dt_over_tc,mass_factor,skin,transient_strain,measured_strain,mu,mu_err,phi,"
                      "phi_err,syy_over_p,syy_err,z,ke_fluct_over_ma2gd2,profile_dev,wall_per_strain,particle_steps_per_s,"
                      "thesis_mu,thesis_phi,status,phi_iso",
                      row.str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main([&] { return run(argc, argv); });
}
