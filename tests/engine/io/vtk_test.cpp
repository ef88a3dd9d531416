// VTK output: grains, contacts, grid fields and the time index, readable by ParaView/OVITO.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "silt/io.hpp"
#include "support/files.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

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

// Three frictional disks, 0 touching 1 and, across the periodic boundary, 2; grain 0 moving and
// spinning.
const char* kThree = R"(
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

}  // namespace

TEST_CASE("VTK: grains with their data, contacts with normal and tangential forces, a time index") {
  auto sim = test::simulation_from(kThree);
  sim->prepare();
  VtkWriter vtk("vtk_test_out");
  vtk.write(sim->model(), sim->state());
  REQUIRE(sim->step());
  vtk.write(sim->model(), sim->state());
  const std::string grains = test::read_file("vtk_test_out/grains_000000.vtu");
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
  const std::string contacts = test::read_file("vtk_test_out/contacts_000000.vtp");
  CHECK(contacts.find("NumberOfLines=\"2\"") != std::string::npos);
  const auto fn = array_of(contacts, "normal_force");
  REQUIRE(fn.size() == 2);
  CHECK(fn[0] == doctest::Approx(1000 * 0.04));
  CHECK(fn[1] == doctest::Approx(1000 * 0.1));
  // The periodic contact is drawn from grain 0 to the image of grain 2 next to it (x = -0.4).
  const auto ends = array_of(contacts, "position");
  CHECK(ends[6 + 3] == doctest::Approx(-0.4));
  const std::string pvd = test::read_file("vtk_test_out/index.pvd");
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
  const std::string grains = test::read_file("vtk_shear_out/grains_000000.vtu");
  // velocity = relative velocity + (0.5 (y - 1), 0, 0).
  CHECK(array_of(grains, "velocity") == std::vector<double>{0.1 + 0.5 * 2, 0.2, 0, 0.5 * 8, 0, 0});
  CHECK(array_of(grains, "velocity_relative_to_shear_flow") == std::vector<double>{0.1, 0.2, 0, 0, 0, 0});
}

TEST_CASE("VTK: the grains' force and the contacts' force vectors, normal and tangential parts") {
  // Grain 0 slides along grain 1 (its velocity and spin are across the contact normal x): after a
  // step the tangential spring carries a force.
  auto sim = test::simulation_from(kThree);
  sim->prepare();
  for (int k = 0; k < 3; ++k) REQUIRE(sim->step());
  VtkWriter vtk("vtk_force_out");
  vtk.write(sim->model(), sim->state());
  const std::string grains = test::read_file("vtk_force_out/grains_000000.vtu"),
                    contacts = test::read_file("vtk_force_out/contacts_000000.vtp");
  const auto gf = array_of(grains, "force");
  REQUIRE(gf.size() == 9);
  for (int i = 0; i < 3; ++i) {
    CHECK(gf[3 * i] == doctest::Approx(sim->state().particle_f[2 * i]));
    CHECK(gf[3 * i + 1] == doctest::Approx(sim->state().particle_f[2 * i + 1]));
    CHECK(gf[3 * i + 2] == 0);
  }
  // Contacts 0-1 and 0-2 (across the periodic boundary), forces on grain 0.
  const auto f = array_of(contacts, "force"), fn = array_of(contacts, "normal_force"),
             ft = array_of(contacts, "tangential_force");
  const auto ends = array_of(contacts, "position");
  REQUIRE(f.size() == 6);
  REQUIRE(ft.size() == 2);
  CHECK(ft[0] > 1e-4 * fn[0]);  // the sliding contact
  for (int c = 0; c < 2; ++c) {
    // Normal: along the line from the partner to grain 0; tangential: the rest of the force.
    double n[3], len = 0;
    for (int k = 0; k < 3; ++k) len += std::pow(ends[6 * c + k] - ends[6 * c + 3 + k], 2);
    for (int k = 0; k < 3; ++k) n[k] = (ends[6 * c + k] - ends[6 * c + 3 + k]) / std::sqrt(len);
    const double along = f[3 * c] * n[0] + f[3 * c + 1] * n[1] + f[3 * c + 2] * n[2];
    CHECK(along == doctest::Approx(fn[c]));
    double rest = 0;
    for (int k = 0; k < 3; ++k) rest += std::pow(f[3 * c + k] - along * n[k], 2);
    CHECK(std::sqrt(rest) == doctest::Approx(ft[c]).epsilon(1e-6));
  }
  // Each grain's force is the sum of its contacts' (no walls, no gravity in this scene).
  CHECK(gf[0] == doctest::Approx(f[0] + f[3]));
  CHECK(gf[1] == doctest::Approx(f[1] + f[4]));
  CHECK(gf[3] == doctest::Approx(-f[0]));
  CHECK(gf[7] == doctest::Approx(-f[4]));
  std::filesystem::remove_all("vtk_force_out");
  // With gravity, the total force, as p[K].f: a falling grain's is m g (it was the state's sum,
  // which holds no gravity: 0).
  auto fall = test::simulation_from(test::read_file(test::scene_path("bounce_dry")));
  fall->prepare();
  VtkWriter gvtk("vtk_gravity_out");
  gvtk.write(fall->model(), fall->state());
  const auto g = array_of(test::read_file("vtk_gravity_out/grains_000000.vtu"), "force");
  REQUIRE(g.size() == 3);
  CHECK(g[2] == doctest::Approx(test::observe(fall->model(), fall->state(), "p[0].fz")));
  CHECK(g[2] == doctest::Approx(fall->model().gravity[2] / fall->state().particle_inv_m[0]));
  CHECK(g[2] < 0);
  std::filesystem::remove_all("vtk_gravity_out");
}

TEST_CASE("VTK image data: scalar and vector grid fields as cell data, read back") {
  GridField p, w;
  p.name = "pressure";
  p.nx = 3;
  p.ny = 2;
  p.nz = 2;
  p.lo = {1, 2, 3};
  p.h = {0.5, 0.25, 1};
  w = p;
  w.name = "vorticity";
  w.components = 3;
  for (int k = 0; k < 12; ++k) p.value.push_back(0.5 * k - 1);
  for (int k = 0; k < 36; ++k) w.value.push_back(k * 0.125 - 2);  // exact in decimal
  write_vti("vtk_fields.vti", {p, w});
  const std::string vti = test::read_file("vtk_fields.vti");
  CHECK(vti.find("<VTKFile type=\"ImageData\"") != std::string::npos);
  CHECK(vti.find("WholeExtent=\"0 3 0 2 0 2\" Origin=\"1 2 3\" Spacing=\"0.5 0.25 1\"") != std::string::npos);
  CHECK(vti.find("<CellData Scalars=\"pressure\" Vectors=\"vorticity\">") != std::string::npos);
  CHECK(vti.find("Name=\"vorticity\" NumberOfComponents=\"3\"") != std::string::npos);
  CHECK(array_of(vti, "pressure") == p.value);
  CHECK(array_of(vti, "vorticity") == w.value);
  std::remove("vtk_fields.vti");
  // Fields on other grids, or not filling theirs, are refused.
  GridField q = p;
  q.nx = 4;
  CHECK_THROWS_WITH_AS(write_vti("vtk_fields.vti", {p, q}), doctest::Contains("not on the grid"), IoError);
  q = p;
  q.value.pop_back();
  CHECK_THROWS_WITH_AS(write_vti("vtk_fields.vti", {q}), doctest::Contains("does not fill"), IoError);
  // In a time series: DIR/fields_NNNNNN.vti, part 2 of the index; none without fields.
  auto sim = test::simulation_from(kThree);
  VtkWriter vtk("vtk_fields_out");
  vtk.write(sim->model(), sim->state());
  vtk.write(sim->model(), sim->state(), {p});
  CHECK_FALSE(std::ifstream("vtk_fields_out/fields_000000.vti").good());
  CHECK(array_of(test::read_file("vtk_fields_out/fields_000001.vti"), "pressure") == p.value);
  const std::string pvd = test::read_file("vtk_fields_out/index.pvd");
  CHECK(pvd.find("part=\"2\" file=\"fields_000001.vti\"") != std::string::npos);
  CHECK(pvd.find("fields_000000") == std::string::npos);
  std::filesystem::remove_all("vtk_fields_out");
}

TEST_CASE("VTK of a paste: every grain's lubrication force, which balances its contact force") {
  // Five disks in a fixed box (two contacts, four lubricated gaps only), solved once: in the
  // quasi-static paste with no external force each grain's lubrication force is minus its contact
  // force (eq. 2.19), to the solve's tolerance.
  auto sim = test::simulation_from(test::kLubricatedFive);

  REQUIRE(sim->step());
  const State& s = sim->state();
  VtkWriter vtk("vtk_paste_out");
  vtk.write(sim->model(), s);
  const std::string grains = test::read_file("vtk_paste_out/grains_000000.vtu");
  const auto lub = array_of(grains, "force_lub"), contact = array_of(grains, "force");
  REQUIRE(lub.size() == 15);
  REQUIRE(contact.size() == 15);
  // The sum over each grain's connections of the stored pair forces (on i from j, and minus it
  // on j).
  const auto pf = double_field(s, find_field("pair_f_lub")->id);
  std::vector<double> sum(15, 0.0);
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
      for (int a = 0; a < 2; ++a) {
        sum[3 * i + a] += pf[2 * p + a];
        sum[3 * s.pair_j[p] + a] -= pf[2 * p + a];
      }
  double scale = 0;
  for (double f : contact) scale = std::max(scale, std::abs(f));
  REQUIRE(scale > 100);  // k_n times an overlap of 0.02
  for (size_t k = 0; k < 15; ++k) {
    CAPTURE(k);
    // Nine significant digits in the file.
    CHECK(lub[k] == doctest::Approx(sum[k]).scale(scale).epsilon(1e-8));
    CHECK(lub[k] == doctest::Approx(-contact[k]).scale(scale).epsilon(1e-8));
  }
  // Only the touching pairs are contact lines; the lubrication is the grains' force_lub.
  CHECK(test::read_file("vtk_paste_out/contacts_000000.vtp").find("NumberOfLines=\"2\"") != std::string::npos);
  std::filesystem::remove_all("vtk_paste_out");
}
