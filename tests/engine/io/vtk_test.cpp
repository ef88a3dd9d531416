// VTK output: grains, contacts and the time index, readable by ParaView/OVITO.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include "silt/io.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The numbers of the DataArray named `name`.
std::vector<double> array_of(const std::string& xml, const std::string& name) {
  const auto at = xml.find("Name=\"" + name + "\"");
  REQUIRE(at != std::string::npos);
  const auto begin = xml.find('>', at) + 1, end = xml.find("</DataArray>", at);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<double> out;
  double x;
  while (in >> x) out.push_back(x);
  return out;
}

}  // namespace

TEST_CASE("VTK: grains with their data, contacts with normal and tangential forces, a time index") {
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [8, 4]
periodic = [true, false]
[contact]
model = "linear"
k_n = 1000
friction = 0.5
[[grains]]
radius = 1.0
placement = "explicit"
positions = [[1.5, 2], [3.46, 2], [7.6, 2]]
velocity = "explicit"
velocities = [[0, 0.1], [0, 0], [0, 0]]
angular_velocities = [[2.0], [0], [0]]
[run]
dt = 1e-3
)";
  auto sim = test::simulation_from(scene);
  sim->prepare();
  VtkWriter vtk("vtk_test_out");
  vtk.write(sim->model(), sim->state());
  REQUIRE(sim->step());
  vtk.write(sim->model(), sim->state());
  const std::string grains = slurp("vtk_test_out/grains_000000.vtu");
  CHECK(grains.find("<VTKFile type=\"UnstructuredGrid\"") != std::string::npos);
  CHECK(grains.find("NumberOfPoints=\"3\"") != std::string::npos);
  const auto x = array_of(grains, "position");
  REQUIRE(x.size() == 9);
  CHECK(x[3] == 3.46);
  CHECK(x[5] == 0);  // z of a 2D grain
  CHECK(array_of(grains, "radius") == std::vector<double>{1, 1, 1});
  CHECK(array_of(grains, "angular_velocity")[2] == 2.0);  // 2D spin in the z component
  CHECK(array_of(grains, "velocity")[1] == doctest::Approx(0.1));
  // Contacts: 0-1 (overlap 0.04) and 2-0 across the periodic boundary (distance 1.9).
  const std::string contacts = slurp("vtk_test_out/contacts_000000.vtp");
  CHECK(contacts.find("NumberOfLines=\"2\"") != std::string::npos);
  const auto fn = array_of(contacts, "normal_force");
  REQUIRE(fn.size() == 2);
  CHECK(fn[0] == doctest::Approx(1000 * 0.04));
  CHECK(fn[1] == doctest::Approx(1000 * 0.1));
  // The periodic contact is drawn from grain 0 to the image of grain 2 next to it (x = -0.4).
  const auto ends = array_of(contacts, "position");
  CHECK(ends[6 + 3] == doctest::Approx(-0.4));
  const std::string pvd = slurp("vtk_test_out/index.pvd");
  CHECK(pvd.find("file=\"grains_000001.vtu\"") != std::string::npos);
  CHECK(pvd.find("file=\"contacts_000001.vtp\"") != std::string::npos);
  CHECK(vtk.count() == 2);
  CHECK_THROWS_AS(VtkWriter("no_such_dir/sub"), IoError);
}

TEST_CASE("VTK under Lees-Edwards shear: the velocity with the shear flow, and relative to it") {
  auto sim = test::simulation_from(R"(
[scene]
dimension = 2
[domain]
lo = [0, 1]
hi = [10, 11]
periodic = [true, true]
[shear]
rate = 0.5
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[2, 3], [7, 9]]
velocity = "explicit"
velocities = [[0.1, 0.2], [0, 0]]
[run]
dt = 1e-3
)");
  VtkWriter vtk("vtk_shear_out");
  vtk.write(sim->model(), sim->state());
  const std::string grains = slurp("vtk_shear_out/grains_000000.vtu");
  // velocity = relative velocity + (0.5 (y - 1), 0, 0).
  CHECK(array_of(grains, "velocity") == std::vector<double>{0.1 + 0.5 * 2, 0.2, 0, 0.5 * 8, 0, 0});
  CHECK(array_of(grains, "velocity_relative_to_shear_flow") == std::vector<double>{0.1, 0.2, 0, 0, 0, 0});
}
