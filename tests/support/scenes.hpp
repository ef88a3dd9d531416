// Test fixtures: scenes built from strings.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "silt/model.hpp"
#include "silt/simulation.hpp"

namespace silt::dem {
struct DemWorkspace;
}

namespace silt::test {

// Parse and compile a scene given as TOML text (throws SceneError).
Model model_from(const std::string& toml, const std::string& name = "test.toml");

// A simulation of that scene.
std::unique_ptr<Simulation> simulation_from(const std::string& toml, int threads = 1);

// The steps of a long run whose bits a test compares with another run's: all of them in the
// Release build, a quarter in the sanitizer build, whose pass over the tests looks for memory and
// undefined-behaviour errors along the same paths (the Release pass compares the whole length).
constexpr int compared_steps(int steps) {
#if defined(SILT_ASAN)
  return steps / 4;
#else
  return steps;
#endif
}

// The message of the SceneError that compiling this scene text raises ("" if it compiles).
std::string scene_error(const std::string& toml);

// Scene text for 2D or 3D: the words LO, HI and PER replaced by the dimension's lists.
std::string with_lists(std::string text, const std::string& lo, const std::string& hi, const std::string& per);

// The neighbour pairs (i, j) listed in the state's pair list.
std::set<std::pair<int, int>> listed_pairs(const State& s);

// The DEM workspace of a simulation (cell lists, pair schedule, contact candidates).
dem::DemWorkspace& dem_workspace(Simulation& sim);

// A scene file of the repository, by name ("chute" -> scenes/chute.toml).
std::string scene_path(const std::string& name);

// A shipped 2D paste scene of 224 disks in a 17 x 17 region (paste_iso, paste_cyclic_*) made a
// quarter of it, 56 disks in 8.5 x 8.5, its dry compression stopped at Phi = 0.8 (prepare.phi;
// paste_iso's then takes 8,300 steps instead of the 312,000 that make it static), written to
// dir/NAME.toml: its path. For tests whose checks depend neither on the size nor on a static
// packing, and whose compressions were the sanitizer pass's longest.
std::string quarter_paste_scene(const std::string& name, const std::string& dir);

// The built `silt` executable.
std::string silt_binary();

}  // namespace silt::test

namespace silt::test {

// Replace every "{key}" of `text` by its value: scene templates with parameters.
std::string fill(std::string text, std::initializer_list<std::pair<const char*, double>> values);

// A periodic box of frictional grains (hooke contacts, radii 0.3 to 0.5, placed at random with
// random velocities): 130 disks in 12 x 12 or 300 spheres in 7 x 7 x 7. Sheared at `shear_rate`
// (Lees-Edwards) unless it is 0; contact.tangential_damping and neighbor.contact_skin as given.
std::string frictional_gas(int dim, double shear_rate, double tangential_damping, double contact_skin);

// Two equal grains approaching head-on along x at relative speed v (no gravity). Run the
// simulation until they separate; returns {restitution, contact duration}.
struct Collision {
  double restitution = 0;
  double duration = 0;
};
Collision head_on_collision(Simulation& sim, double v_rel);

// The largest |a[i] - b[i]| of two arrays of the same length.
double max_diff(const std::vector<double>& a, const std::vector<double>& b);

// n independent standard normal numbers from a seeded generator (mt19937_64).
Eigen::VectorXd gaussian_vector(int64_t n, unsigned seed);

// |a - b| / |b| in the 2-norm: how far a solution is from a reference.
inline double rel_diff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

// The value of one observable of the state, as silt run's stats would sample it.
double observe(const Model& m, const State& s, const std::string& name);

// A lubricated paste of frictional disks (radii 0.35 to 0.5, linear contacts k_n = 1e4, friction
// 0.3) placed at random in a periodic L x L box at an imposed pressure P = 1. With a dilation,
// compressed dry to a static packing first (or until Phi = `phi`, when given) and then dilated by
// it (a paste's initial state, Peyneau 2009 sec. 2.3.1). `lubrication` holds more lines of the
// [lubrication] table.
struct PasteDisks {
  double n = 60;
  double L = 9;
  double h_min = 1e-2;
  double viscosity = 1;
  double density = 1;
  double dilation = 0;  // 0: no dry compression first
  double phi = 0;       // 0: the compression goes on until static
  unsigned seed = 7;
  double length = 1;  // the unit of length: the radii and the box times it
  std::string lubrication = "";
};
std::string paste_disks(const PasteDisks& p);

// A lubricated paste of five disks of radius 0.5 (h_max = 0.5) in a fixed periodic box, a fixed
// step: 0-1 and 1-2 touch (overlaps 0.02 and 0.005), 1-3, 2-3, 0-4 and 1-4 are lubricated gaps
// only (0.011 to 0.22). With no external force, one solve gives the contacts' own lubrication
// the contact forces to balance (eq. 2.19); the gaps carry about 1e-11.
inline const char* kLubricatedFive = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [8, 8]
periodic = [true, true]
[contact]
model = "linear"
k_n = 1e4
[lubrication]
viscosity = 1.0
h_min_over_a = 1e-2
tolerance = 1e-12
dt = 1e-3
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[3.0, 4.0], [3.98, 4.0], [4.577, 4.796], [5.2, 4.0], [3.5, 3.1]]
)";

}  // namespace silt::test
