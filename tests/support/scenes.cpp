#include "support/scenes.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/workspace.hpp"
#include "dem/workspace.hpp"
#include "silt/observables.hpp"
#include "silt/scene.hpp"
#include "support/files.hpp"

namespace silt::test {

dem::DemWorkspace& dem_workspace(Simulation& sim) { return sim.workspaces().get<dem::DemWorkspace>(); }

Model model_from(const std::string& toml, const std::string& name) { return compile(parse_scene(toml, name)); }

std::unique_ptr<Simulation> simulation_from(const std::string& toml, int threads) {
  return std::make_unique<Simulation>(model_from(toml), threads);
}

std::string scene_error(const std::string& toml) {
  try {
    model_from(toml, "bad.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

std::string with_lists(std::string text, const std::string& lo, const std::string& hi, const std::string& per) {
  for (auto [key, value] : {std::pair{"LO", lo}, std::pair{"HI", hi}, std::pair{"PER", per}})
    text.replace(text.find(key), std::string(key).size(), value);
  return text;
}

std::string frictional_gas(int dim, double shear_rate, double tangential_damping, double contact_skin) {
  const char* text = R"(
[scene]
dimension = {dim}
seed = 5
[domain]
lo = LO
hi = HI
periodic = PER
[contact]
model = "hooke"
k_n = 1e4
gamma_n = 20
friction = 0.4
tangential_damping = {zt}
[[grains]]
count = {n}
radius_min = 0.3
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 1.0
[neighbor]
skin = 0.3
contact_skin = {cs}
[run]
dt = 1e-3
)";
  const bool d3 = dim == 3;
  std::string scene = fill(with_lists(text, d3 ? "[0, 0, 0]" : "[0, 0]", d3 ? "[7, 7, 7]" : "[12, 12]",
                                      d3 ? "[true, true, true]" : "[true, true]"),
                           {{"dim", dim}, {"n", d3 ? 300 : 130}, {"zt", tangential_damping}, {"cs", contact_skin}});
  if (shear_rate != 0) scene += "[shear]\nrate = " + fill("{g}", {{"g", shear_rate}}) + "\n";
  return scene;
}

std::set<std::pair<int, int>> listed_pairs(const State& s) {
  std::set<std::pair<int, int>> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) out.insert({static_cast<int>(i), s.pair_j[p]});
  return out;
}

std::string scene_path(const std::string& name) { return std::string(SILT_SOURCE_DIR) + "/scenes/" + name + ".toml"; }

std::string silt_binary() { return SILT_BINARY; }

std::string quarter_paste_scene(const std::string& name, const std::string& dir) {
  std::string toml = read_file(scene_path(name));
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"count = 224", "count = 56"},
                                 {"hi = [17.0, 17.0]", "hi = [8.5, 8.5]"},
                                 {"compress = true", "compress = true\nphi = 0.8"}}) {
    const auto at = toml.find(from);
    if (at == std::string::npos) throw std::runtime_error(name + ": no '" + from + "' to make a quarter of");
    toml.replace(at, from.size(), to);
  }
  const std::string path = dir + "/" + name + ".toml";
  std::ofstream(path) << toml;
  return path;
}

}  // namespace silt::test

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace silt::test {

std::string fill(std::string text, std::initializer_list<std::pair<const char*, double>> values) {
  for (const auto& [key, value] : values) {
    std::ostringstream o;
    o.precision(17);
    o << value;
    std::string v = o.str();
    if (v.find_first_of(".e") == std::string::npos) v += ".0";
    const std::string k = std::string("{") + key + "}";
    for (size_t pos = text.find(k); pos != std::string::npos; pos = text.find(k, pos + v.size()))
      text.replace(pos, k.size(), v);
  }
  return text;
}

std::string paste_disks(const PasteDisks& p) {
  const char* text = R"([scene]
dimension = 2
seed = {seed}
[domain]
lo = [0, 0]
hi = [{Lx}, {Lx}]
periodic = [true, true]
[box]
pressure = 1.0
{prepare}[contact]
model = "linear"
k_n = 1e4
friction = 0.3
kt_over_kn = 0.5
damping = 0.9
tangential_damping = 0.5
[run]
dt_over_tc = 0.05
[lubrication]
viscosity = {eta}
h_min_over_a = {hmin}
{lubrication}
[[grains]]
count = {n}
radius_min = {rmin}
radius_max = {rmax}
density = {rho}
placement = "random"
)";
  std::string s = text;
  std::string prepare = p.dilation > 0 ? "[prepare]\ncompress = true\ndilation = {dilation}\n" : "";
  if (p.dilation > 0 && p.phi > 0) prepare += "phi = {phi}\n";
  s.replace(s.find("{prepare}"), 9, prepare);
  s.replace(s.find("{lubrication}"), 13, p.lubrication);
  s.replace(s.find("{seed}"), 6, std::to_string(p.seed));
  return fill(s, {{"n", p.n},
                  {"Lx", p.L * p.length},
                  {"hmin", p.h_min},
                  {"eta", p.viscosity},
                  {"rho", p.density},
                  {"dilation", p.dilation},
                  {"phi", p.phi},
                  {"rmin", 0.35 * p.length},
                  {"rmax", 0.5 * p.length}});
}

Collision head_on_collision(Simulation& sim, double v_rel) {
  Collision c;
  const State& s = sim.state();
  const int D = s.dim;
  int64_t touching = 0;
  bool started = false;
  for (int64_t k = 0; k < 10'000'000; ++k) {
    if (!sim.step()) break;
    double d2 = 0;
    for (int a = 0; a < D; ++a) {
      const double d = s.particle_x[a] - s.particle_x[D + a];
      d2 += d * d;
    }
    const bool touch = std::sqrt(d2) < s.particle_r[0] + s.particle_r[1];
    if (touch) {
      started = true;
      ++touching;
    } else if (started) {
      break;
    }
  }
  c.duration = touching * s.dt;
  c.restitution = (s.particle_v[D] - s.particle_v[0]) / v_rel;  // grain 0 moves +x, grain 1 -x
  return c;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

Eigen::VectorXd gaussian_vector(int64_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  Eigen::VectorXd v(n);
  for (int64_t i = 0; i < n; ++i) v[i] = gauss(rng);
  return v;
}

double observe(const Model& m, const State& s, const std::string& name) { return Observer(m, {name}).sample(m, s)[0]; }

}  // namespace silt::test
