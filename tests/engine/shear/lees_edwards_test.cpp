// Lees-Edwards simple shear (flow along x, gradient along y): image arithmetic, grains crossing
// the sheared boundary, the affine flow, neighbour lists and contacts across the boundary, the
// stress of a contact seen through it, the imposed pressure and shear stress, observables and
// scene errors. The image of a grain at (x, y) one period up is at (x + le_offset, y + L_y).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "dem/stages.hpp"
#include "silt/contacts.hpp"
#include "silt/observables.hpp"
#include "silt/periodic_image.hpp"
#include "silt/scene.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

using D3 = std::array<double, 3>;

Box sheared_box(int dim, D3 lo, D3 len, double offset) {
  Box b;
  b.lo = lo;
  b.len = len;
  for (int k = 0; k < dim; ++k) b.periodic[k] = true;
  b.lees_edwards = true;
  b.le_offset = offset;
  return b;
}

// Nearest image of a separation by exhaustive search over the lattice of images, independent of
// the engine's arithmetic: the images of a grain are at x + a (offset, L_y, 0) + b (L_x, 0, 0)
// + c (0, 0, L_z) for integers a, b, c, so a separation d = x_i - x_j has the images
// d - a (offset, L_y, 0) - b (L_x, 0, 0) - c (0, 0, L_z). `span` bounds |a|, |c| and |b| / 2.
D3 nearest_by_search(const Box& box, const D3& d, int dim, int span = 1) {
  D3 best = d;
  double best2 = 1e300;
  const int cz = dim == 3 ? span : 0;
  for (int a = -span; a <= span; ++a)
    for (int b = -2 * span; b <= 2 * span; ++b)
      for (int c = -cz; c <= cz; ++c) {
        D3 e = d;
        e[0] -= a * box.le_offset + b * box.len[0];
        e[1] -= a * box.len[1];
        e[2] -= c * box.len[2];
        double e2 = 0;
        for (int k = 0; k < dim; ++k) e2 += e[k] * e[k];
        if (e2 < best2) {
          best2 = e2;
          best = e;
        }
      }
  return best;
}

double norm(const D3& d, int dim) {
  double s = 0;
  for (int k = 0; k < dim; ++k) s += d[k] * d[k];
  return std::sqrt(s);
}

// Whether some image of the separation d is shorter than reach: the exhaustive search of
// nearest_by_search (images a, b, c in [-1, 1] x [-2, 2] x [-1, 1], enough for two points of the
// box), pruned on y and z first.
bool within(const Box& box, const D3& d, int dim, double reach) {
  const double r2 = reach * reach;
  for (int a = -1; a <= 1; ++a) {
    const double ey = d[1] - a * box.len[1];
    if (ey * ey >= r2) continue;
    for (int c = dim == 3 ? -1 : 0; c <= (dim == 3 ? 1 : 0); ++c) {
      const double ez = dim == 3 ? d[2] - c * box.len[2] : 0.0;
      if (ey * ey + ez * ez >= r2) continue;
      for (int b = -2; b <= 2; ++b) {
        const double ex = d[0] - a * box.le_offset - b * box.len[0];
        if (ex * ex + ey * ey + ez * ez < r2) return true;
      }
    }
  }
  return false;
}

// Pairs i < j of the state closer than r_i + r_j + extra, by brute force over all pairs.
std::set<std::pair<int, int>> pairs_within(const State& s, double extra) {
  const int D = s.dim;
  std::set<std::pair<int, int>> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int64_t j = i + 1; j < s.n; ++j) {
      D3 d{0, 0, 0};
      for (int k = 0; k < D; ++k) d[k] = s.particle_x[D * i + k] - s.particle_x[D * j + k];
      if (within(s.box, d, D, s.particle_r[i] + s.particle_r[j] + extra))
        out.insert({static_cast<int>(i), static_cast<int>(j)});
    }
  return out;
}

std::set<std::pair<int, int>> touching(const State& s) {
  std::set<std::pair<int, int>> out;
  for (const Contact& c : touching_contacts(s)) out.insert({static_cast<int>(c.i), static_cast<int>(c.j)});
  return out;
}

// Distance between a and b on a circle of circumference len.
double periodic_gap(double a, double b, double len) {
  const double d = a - b;
  return std::abs(d - len * std::nearbyint(d / len));
}

}  // namespace

// ---- 1. image arithmetic ---------------------------------------------------------------------

TEST_CASE("Lees-Edwards nearest image: hand-computed separations through the sheared boundary") {
  // 2D box L = (10, 8), offset 3. Every expected value below is worked out by hand from the
  // images of grain j, (x_j + offset, y_j + L_y) one period up and (x_j - offset, y_j - L_y) one
  // period down, then the x images.
  const Box b = sheared_box(2, {-3, 2, 0}, {10, 8, 1}, 3.0);
  auto near = [&](double dx, double dy) {
    double d[3] = {dx, dy, 0};
    b.nearest(d, 2);
    return std::pair{d[0], d[1]};
  };
  // i at (5, 9.5), j at (4, 2.5): d = (1, 7); j's image above at (7, 10.5) gives (-2, -1).
  auto [x1, y1] = near(1, 7);
  CHECK(x1 == doctest::Approx(-2.0));
  CHECK(y1 == doctest::Approx(-1.0));
  // d = (-1, -7.5): the image below, shifted by -offset, gives (-1 + 3, 0.5) = (2, 0.5).
  auto [x2, y2] = near(-1, -7.5);
  CHECK(x2 == doctest::Approx(2.0));
  CHECK(y2 == doctest::Approx(0.5));
  // Inside the box, no image in y: plain x wrap only (the offset must not enter).
  auto [x3, y3] = near(7, 1);
  CHECK(x3 == doctest::Approx(-3.0));
  CHECK(y3 == doctest::Approx(1.0));

  // Offset close to L_x: after the shift the x wrap matters.
  const Box c = sheared_box(2, {0, 0, 0}, {10, 8, 1}, 9.5);
  {
    double d[3] = {4, 7, 0};  // (4 - 9.5, -1) = (-5.5, -1), wrapped in x to (4.5, -1)
    c.nearest(d, 2);
    CHECK(d[0] == doctest::Approx(4.5));
    CHECK(d[1] == doctest::Approx(-1.0));
    double e[3] = {-4, -6, 0};  // (-4 + 9.5, 2) = (5.5, 2), wrapped to (-4.5, 2)
    c.nearest(e, 2);
    CHECK(e[0] == doctest::Approx(-4.5));
    CHECK(e[1] == doctest::Approx(2.0));
  }
  // 3D: z is an ordinary periodic direction, not touched by the shift.
  const Box b3 = sheared_box(3, {0, 0, 0}, {10, 8, 6}, 9.5);
  {
    double d[3] = {4, 7, 5};  // (4.5, -1, -1)
    b3.nearest(d, 3);
    CHECK(d[0] == doctest::Approx(4.5));
    CHECK(d[1] == doctest::Approx(-1.0));
    CHECK(d[2] == doctest::Approx(-1.0));
    double e[3] = {0.5, -7.25, -2};  // (0.5 + 9.5, 0.75) -> (0, 0.75), z unchanged
    b3.nearest(e, 3);
    CHECK(std::abs(e[0]) < 1e-12);
    CHECK(e[1] == doctest::Approx(0.75));
    CHECK(e[2] == doctest::Approx(-2.0));
  }
  // The kernels' PeriodicImage gives the same numbers.
  {
    const PeriodicImage<3> img(b3);
    Vec3 d(4, 7, 5);
    img.apply(d);
    CHECK(d[0] == doctest::Approx(4.5));
    CHECK(d[1] == doctest::Approx(-1.0));
    CHECK(d[2] == doctest::Approx(-1.0));
    const PeriodicImage<2> img2(c);
    Vec2 e(-4, -6);
    img2.apply(e);
    CHECK(e[0] == doctest::Approx(-4.5));
    CHECK(e[1] == doctest::Approx(2.0));
  }
}

TEST_CASE("Lees-Edwards nearest image agrees with an exhaustive search over the images") {
  // For any separation whose true nearest image is shorter than half of every box length (all
  // that interactions ever need), Box::nearest and PeriodicImage::apply must return exactly that
  // image. Random separations spanning several periods, offsets over [0, L_x).
  uint64_t seed = 12345;
  auto uniform = [&](double a, double b) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return a + (b - a) * static_cast<double>(seed >> 11) * (1.0 / 9007199254740992.0);
  };
  int tested = 0;
  for (int dim : {2, 3}) {
    for (int trial = 0; trial < 4000; ++trial) {
      const D3 len{uniform(4, 12), uniform(4, 12), dim == 3 ? uniform(4, 12) : 1.0};
      const Box b = sheared_box(dim, {uniform(-5, 5), uniform(-5, 5), uniform(-5, 5)}, len, uniform(0, len[0]));
      // Separations of two points in the box, or a few periods further.
      D3 d{uniform(-len[0], len[0]), uniform(-len[1], len[1]), dim == 3 ? uniform(-len[2], len[2]) : 0.0};
      if (trial % 3 == 0)
        for (int k = 0; k < dim; ++k) d[k] += len[k] * std::floor(uniform(-2, 3));
      const D3 want = nearest_by_search(b, d, dim, 4);
      const double half = 0.5 * std::min({len[0], len[1], dim == 3 ? len[2] : 1e300});
      if (norm(want, dim) >= half) continue;
      ++tested;
      D3 got = d;
      b.nearest(got.data(), dim);
      for (int k = 0; k < dim; ++k) REQUIRE(got[k] == doctest::Approx(want[k]).epsilon(1e-12).scale(10));
      if (dim == 2) {
        Vec2 v(d[0], d[1]);
        PeriodicImage<2>(b).apply(v);
        for (int k = 0; k < 2; ++k) REQUIRE(v[k] == got[k]);
      } else {
        Vec3 v(d[0], d[1], d[2]);
        PeriodicImage<3>(b).apply(v);
        for (int k = 0; k < 3; ++k) REQUIRE(v[k] == got[k]);
      }
    }
  }
  CHECK(tested > 1000);  // the filter keeps a good share of the draws
}

TEST_CASE("PeriodicImage wrap of a point leaving through the top or the bottom of a sheared box") {
  // lo = (-3, 2), L = (10, 8), offset 7.5. Through the top: y - L_y, x - offset; through the
  // bottom: y + L_y, x + offset; then x wrapped into [-3, 7).
  const Box b = sheared_box(2, {-3, 2, 0}, {10, 8, 1}, 7.5);
  const PeriodicImage<2> img(b);
  struct Case {
    double x, y, want_x, want_y;
  };
  const Case cases[] = {
      {5, 10.3, -2.5, 2.3},         // top: x 5 - 7.5 = -2.5, inside
      {-2.9, 10.1, -0.4, 2.1},      // top: x -10.4, wrapped to -0.4
      {-2, 1.8, 5.5, 9.8},          // bottom: x -2 + 7.5 = 5.5
      {6, 1.5, 3.5, 9.5},           // bottom: x 13.5, wrapped to 3.5
      {8, 5, -2, 5},                // no y crossing: x wrap only, no shift
      {1, 18.5, 1 - 15 + 20, 2.5},  // two periods up: x - 2 offset, wrapped
  };
  for (const Case& c : cases) {
    CAPTURE(c.x);
    CAPTURE(c.y);
    Vec2 p(c.x, c.y);
    img.wrap(p, b);
    CHECK(p[0] == doctest::Approx(c.want_x).scale(10));
    CHECK(p[1] == doctest::Approx(c.want_y).scale(10));
    CHECK(p[0] >= -3);
    CHECK(p[0] < 7);
    CHECK(p[1] >= 2);
    CHECK(p[1] < 10);
  }
  // A hair below the bottom: y + L_y rounds onto the upper edge lo_y + L_y, which is the image
  // one more period down, at y = lo_y. The grain must stay where it is (x = 1, y = lo_y), not
  // jump by the offset.
  {
    Vec2 p(1, std::nextafter(2.0, 0.0));
    img.wrap(p, b);
    CHECK(p[0] == doctest::Approx(1.0));
    CHECK(p[1] == doctest::Approx(2.0));
    CHECK(p[1] < 10);
  }
  // 3D: z wrapped independently of the shift.
  const Box b3 = sheared_box(3, {0, 0, 0}, {10, 8, 6}, 2.25);
  Vec3 p(1, 8.5, 6.5);
  PeriodicImage<3>(b3).wrap(p, b3);
  CHECK(p[0] == doctest::Approx(8.75));  // 1 - 2.25 + 10
  CHECK(p[1] == doctest::Approx(0.5));
  CHECK(p[2] == doctest::Approx(0.5));
}

// ---- 2. a grain crossing the sheared boundary ------------------------------------------------

TEST_CASE("a free grain crossing the sheared boundary moves in a straight line, shifted by the offset") {
  // One grain, no contact, no gravity: Newton's first law. Its velocity u = c + gd (y - lo_y) e_x
  // is constant, so the stored velocity c (relative to the flow) changes as
  //   c_x(t) = vx - gd vy t,   c_y = vy,
  // and, unwrapped, it moves along
  //   Y(t) = y0 + vy t,   X(t) = x0 + (vx + gd (y0 - lo_y)) t.
  // After k crossings of the top (k < 0: bottom) its stored position is the image k periods
  // down, (X - k offset(t), Y - k L_y) with offset(t) = gd L_y t, wrapped in x; c is continuous
  // across the boundary and u jumps by -k gd L_y.
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [-2, 1]
hi = [8, 11]
periodic = [true, true]
[shear]
rate = {gd}
[contact]
model = "linear"
k_n = 1e3
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[{x0}, {y0}]]
velocity = "explicit"
velocities = [[{vx}, {vy}]]
[run]
dt = 1e-3
)";
  const double gd = 0.7, L = 10, lo_x = -2, lo_y = 1, dt = 1e-3;
  for (double vy : {1.0, -1.0}) {
    CAPTURE(vy);
    // 0.3005 or 0.2005 from the boundary: no crossing falls on a step.
    const double x0 = 3.0, y0 = vy > 0 ? 10.6995 : 1.2005, vx = 0.25;
    auto sim = test::simulation_from(test::fill(scene, {{"gd", gd}, {"x0", x0}, {"y0", y0}, {"vx", vx}, {"vy", vy}}));
    const State& s = sim->state();
    int crossed_at = -1;
    for (int step = 1; step <= 600; ++step) {
      const double y_before = s.particle_x[1], x_before = s.particle_x[0];
      const double cx_before = s.particle_v[0];
      REQUIRE(sim->step());
      const double t = step * dt;
      // The stored velocity is relative to the flow: it follows the flow's change along the
      // path, crossing or not (rounding of ~600 steps of O(1) values).
      REQUIRE(std::abs(s.particle_v[0] - (vx - gd * vy * t)) < 1e-12);
      REQUIRE(s.particle_v[1] == vy);
      const double X = x0 + (vx + gd * (y0 - lo_y)) * t, Y = y0 + vy * t;
      const double k = std::floor((Y - lo_y) / L);
      // Rounding of ~600 steps of O(10) values: far below 1e-9 L.
      REQUIRE(std::abs(s.particle_x[1] - (Y - k * L)) < 1e-9 * L);
      REQUIRE(periodic_gap(s.particle_x[0], X - k * gd * L * t, L) < 1e-9 * L);
      REQUIRE(s.particle_x[0] >= lo_x);
      REQUIRE(s.particle_x[0] < lo_x + L);
      if (std::abs(s.particle_x[1] - y_before) > 0.5 * L) {
        REQUIRE(crossed_at < 0);
        crossed_at = step;
        // Across the boundary, x moved by u_x dt minus (top) or plus (bottom) the offset.
        const double u_before = cx_before + gd * (y_before - lo_y);
        const double sign = vy > 0 ? 1.0 : -1.0;
        CHECK(periodic_gap(s.particle_x[0], x_before + dt * u_before - sign * s.box.le_offset, L) < 1e-12 * L);
        // u_x jumps by -gd L_y going up, +gd L_y going down.
        const double u_after = s.particle_v[0] + gd * (s.particle_x[1] - lo_y);
        CHECK(std::abs((u_after - u_before) + sign * gd * L) <= 1e-12 * gd * L);
      }
    }
    CHECK(crossed_at == (vy > 0 ? 301 : 201));
    CHECK(s.box.le_offset == doctest::Approx(std::fmod(gd * L * 600 * dt, L)));
  }
}

// ---- 3. the affine flow ------------------------------------------------------------------------

TEST_CASE("an affine shear flow of free grains stays affine through several turns of the offset") {
  // Grains on distinct heights 1 apart (radius 0.3: they never meet, also across the boundary),
  // two per height. Velocities relative to the flow zero, or one uniform initial (u, w) for all (relative
  // positions are then those of the zero case, and the grains cross the sheared boundary). The
  // exact path of each is the straight line of the single-grain test; gd t = 3 makes the offset
  // turn three times around L_x. 3000 steps of rounding on O(10) values stay far below 1e-9 L.
  const char* scene = R"(
[scene]
dimension = {dim}
[domain]
lo = LO
hi = HI
periodic = PER
[shear]
rate = 1.0
[contact]
model = "hooke"
k_n = 1e3
[[grains]]
radius = 0.3
placement = "explicit"
positions = POS
velocity = "explicit"
velocities = VEL
[run]
dt = 1e-3
)";
  for (int dim : {2, 3}) {
    for (bool drift : {false, true}) {
      CAPTURE(dim);
      CAPTURE(drift);
      const D3 lo{-2, 1, 0}, len{10, 10, 6};
      const double u = drift ? 0.15 : 0.0, w = drift ? 0.9 : 0.0, gd = 1.0, dt = 1e-3;
      std::vector<D3> x0;
      std::string pos = "[", vel = "[";
      for (int level = 0; level < 10; ++level)
        for (int twin = 0; twin < 2; ++twin) {
          const D3 p{lo[0] + std::fmod(0.37 * level + 5.0 * twin, 10.0), lo[1] + 0.5 + level, 0.5 + 0.5 * level};
          x0.push_back(p);
          auto num = [](double v) { return test::fill("{v}", {{"v", v}}); };
          pos += "[" + num(p[0]) + ", " + num(p[1]) + (dim == 3 ? ", " + num(p[2]) : "") + "],";
          vel += "[" + num(u) + ", " + num(w) + (dim == 3 ? ", 0.0" : "") + "],";
        }
      pos.back() = ']';
      vel.back() = ']';
      std::string text =
          test::with_lists(scene, dim == 3 ? "[-2, 1, 0]" : "[-2, 1]", dim == 3 ? "[8, 11, 6]" : "[8, 11]",
                           dim == 3 ? "[true, true, true]" : "[true, true]");
      text.replace(text.find("POS"), 3, pos);
      text.replace(text.find("VEL"), 3, vel);
      auto sim = test::simulation_from(test::fill(text, {{"dim", dim}}));
      const State& s = sim->state();
      const int steps = 3000;
      int crossings = 0;
      for (int step = 1; step <= steps; ++step) {
        REQUIRE(sim->step());
        if (step % 100 != 0 && step != steps) continue;
        const double t = step * dt;
        for (int64_t i = 0; i < s.n; ++i) {
          const int id = s.particle_id[i];
          CAPTURE(id);
          // No force ever acts: the velocity relative to the flow follows the flow's change
          // along the path (exactly zero without the uniform velocity).
          if (drift) REQUIRE(std::abs(s.particle_v[dim * i] - (u - gd * w * t)) < 1e-11);
          else REQUIRE(s.particle_v[dim * i] == 0.0);
          REQUIRE(s.particle_v[dim * i + 1] == w);
          if (dim == 3) REQUIRE(s.particle_v[dim * i + 2] == 0.0);
          const double Y = x0[id][1] + w * t, X = x0[id][0] + (u + gd * (x0[id][1] - lo[1])) * t;
          const double k = std::floor((Y - lo[1]) / len[1]);
          if (step == steps) crossings += k != 0;
          REQUIRE(std::abs(s.particle_x[dim * i + 1] - (Y - k * len[1])) < 1e-9 * len[1]);
          REQUIRE(periodic_gap(s.particle_x[dim * i], X - k * gd * len[1] * t, len[0]) < 1e-9 * len[0]);
          if (dim == 3) REQUIRE(s.particle_x[dim * i + 2] == x0[id][2]);
        }
      }
      CHECK(s.shear_strain == doctest::Approx(3.0).epsilon(1e-12));
      CHECK(s.le_displacement == doctest::Approx(30.0).epsilon(1e-12));  // three turns of L_x
      CHECK(crossings == (drift ? 6 : 0));  // the top three levels (w t = 2.7) have crossed
    }
  }
}

TEST_CASE("with L_x following the pressure the sheared image lattice deforms with the grains") {
  // Two free grains at rest relative to the flow, A near the top and B near the bottom, in a box
  // whose L_x follows a small pressure (no contact: sigma_xx = 0 < P, so L_x shrinks by about
  // 0.5 % over the run) while L_y is fixed. Every material separation is carried by the affine
  // flow; in particular the one between A and the image of B one period up,
  //   d = x_A - (x_B + offset, y_B + L_y),
  // must follow d_x <- lambda_x d_x + dt gd d_y per step (lambda_x = L_x(t + dt) / L_x(t)),
  // d_y constant, like any pair inside the box: the offset of the image lattice has to stretch
  // with L_x. Rounding only: 1e-9 L.
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [10, 10]
periodic = [true, true]
[box]
pressure = 1e-3
controlled = [true, false]
[shear]
rate = 1.0
[contact]
model = "hooke"
k_n = 1e3
[[grains]]
radius = 0.3
placement = "explicit"
positions = [[4, 9.5], [4.5, 0.5]]
[run]
dt = 1e-3
)";
  auto sim = test::simulation_from(scene);
  const State& s = sim->state();
  const double gd = 1.0, dt = 1e-3, L_y = 10;
  // Through the boundary at t = 0 (offset 0): A - (B + (0, L_y)).
  double dx = 4 - 4.5, dy = 9.5 - 0.5 - L_y;
  double L_x = s.box.len[0];
  auto engine_dx = [&] {  // A minus B's image one period up, in the engine's current box
    return s.particle_x[0] - (s.particle_x[2] + s.box.le_offset);
  };
  for (int step = 1; step <= 2500; ++step) {
    REQUIRE(sim->step());
    const double lambda = s.box.len[0] / L_x;
    L_x = s.box.len[0];
    dx = lambda * dx + dt * gd * dy;
    for (double v : s.particle_v) REQUIRE(v == 0);  // at rest relative to the flow
    REQUIRE(s.particle_x[1] == 9.5);
    REQUIRE(s.particle_x[3] == 0.5);
    if (step % 100 == 0) REQUIRE(periodic_gap(engine_dx(), dx, L_x) < 1e-9 * L_x);
  }
  CHECK(s.box.len[0] < 0.997 * 10);    // the box did shrink
  CHECK(s.le_displacement > 2 * L_x);  // the offset turned twice
}

// ---- 4. neighbour lists and contacts across the boundary ------------------------------------

TEST_CASE("under Lees-Edwards the cell list finds exactly the pairs and contacts of a brute-force search") {
  const char* scene = R"(
[scene]
dimension = {dim}
seed = {seed}
[domain]
lo = LO
hi = HI
periodic = PER
[shear]
rate = 2.0
[contact]
model = "hooke"
k_n = 1e4
gamma_n = 20
friction = 0.3
[[grains]]
count = {n}
radius_min = 0.2
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 1e-4
[neighbor]
skin = 0.3
[run]
dt = 1e-3
)";
  struct Setup {
    int dim, n;
    const char *lo, *hi, *per;
  };
  // Cells are >= 2 r_max + skin = 1.3: 6 x 5 x 3 cells in 3D, 9 x 5 in 2D, a narrow 2D box of 2
  // cells along x where the shifted stencil wraps onto itself, and one of 2 cells along y where
  // the rows above and below are the same row, once shifted and once not.
  const Setup setups[] = {
      {3, 380, "[-3, 0, 1]", "[5, 7.5, 6]", "[true, true, true]"},
      {2, 90, "[-3, 0]", "[9, 6.5]", "[true, true]"},
      {2, 22, "[0, 0]", "[2.7, 8]", "[true, true]"},
      {2, 22, "[0, 0]", "[8, 2.7]", "[true, true]"},
  };
  for (const Setup& st : setups) {
    for (int seed : {1, 2}) {
      CAPTURE(st.dim);
      CAPTURE(st.n);
      CAPTURE(seed);
      auto sim = test::simulation_from(
          test::fill(test::with_lists(scene, st.lo, st.hi, st.per), {{"dim", st.dim}, {"seed", seed}, {"n", st.n}}), 2);
      const Model& m = sim->model();
      State& s = sim->state();
      sim->prepare();
      // Shear for a strain of 0.6 (the offset moves by 0.6 L_y, a good part of L_x). Every 15th
      // step, every touching pair must be in the kept list (the skin criterion with the affine
      // strain) and touching_contacts must find exactly them.
      int64_t contacts_seen = 0, across_seen = 0;
      auto across = [&](const std::set<std::pair<int, int>>& pairs) {  // through the sheared boundary
        int64_t c = 0;
        for (auto [i, j] : pairs)
          c += std::abs(s.particle_x[st.dim * i + 1] - s.particle_x[st.dim * j + 1]) > 0.5 * s.box.len[1];
        return c;
      };
      for (int step = 1; step <= 300; ++step) {
        REQUIRE(sim->step());
        if (step % 15 != 0) continue;
        const auto want = pairs_within(s, 0.0);
        REQUIRE(touching(s) == want);
        contacts_seen += static_cast<int64_t>(want.size());
        across_seen += across(want);
      }
      CHECK(s.box.le_offset > 0);
      CHECK(contacts_seen > 0);  // the shear brought grains into contact
      // Fresh lists at these positions for offsets across [0, L_x): shifts by whole and
      // fractional cells, half the box, just below L_x.
      const double lx = s.box.len[0], cell = lx / std::floor(lx / m.interaction_range());
      for (double off : {0.0, 0.37 * cell, cell, 1.5 * cell, 0.5 * lx, lx - 0.6 * cell, lx - 1e-9, s.box.le_offset}) {
        CAPTURE(off);
        s.box.le_offset = off;
        s.nbr_valid = false;
        dem::update_neighbors(m, s, test::dem_workspace(*sim));
        const auto list = test::listed_pairs(s);
        CHECK(static_cast<int64_t>(list.size()) == s.n_pairs());  // no duplicate
        const auto near = pairs_within(s, m.skin);
        CHECK(list == near);
        across_seen += across(near);
        const auto want = pairs_within(s, 0.0);
        CHECK(touching(s) == want);
        // The force stage sees the same contacts: a force on exactly the touching pairs.
        dem::contact_forces(m, s, test::dem_workspace(*sim));
        std::set<std::pair<int, int>> forced;
        for (int64_t i = 0; i < s.n; ++i)
          for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
            double f2 = 0;
            for (int k = 0; k < st.dim; ++k) f2 += s.pair_f[st.dim * p + k] * s.pair_f[st.dim * p + k];
            if (f2 > 0) forced.insert({static_cast<int>(i), s.pair_j[p]});
          }
        CHECK(forced == want);
      }
      CHECK(across_seen > 0);  // pairs through the sheared boundary were part of the comparisons
    }
  }
}

// ---- 5. stress of a contact through the boundary ----------------------------------------------

TEST_CASE("stress of two grains touching through the sheared boundary: f (x) d / V, compression positive") {
  // Two disks of radius 0.5 in a 10 x 10 box; grain 0 at (1, 0.2) and grain 1 near the top,
  // placed so that the image of grain 1 one period down, (x1 - offset, y1 - 10), is at
  // d = 0.95 (cos th, sin th) from grain 0: overlap 0.05, touching only through the sheared
  // boundary (without the shift they are more than a diameter apart). Linear law k_n = 1000:
  // f = k 0.05 n on grain 0, so sigma_ab = k 0.05 n_a d_b / V.
  const char* scene = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [10, 10]
periodic = [true, true]
[shear]
KEY = {value}
[contact]
model = "linear"
k_n = 1000
damping = {zeta}
[[grains]]
radius = 0.5
placement = "explicit"
positions = [[1, 0.2], [{x1}, {y1}]]
[run]
dt = 1e-3
)";
  const double k = 1000, V = 100, dist = 0.95, overlap = 0.05, pi = 3.14159265358979324;
  const double m_eff = 0.5 * pi * 0.25;  // density 1 per area
  struct Case {
    double theta_deg, offset, rate, zeta;
  };
  const Case cases[] = {
      {60, 3.0, 0.0, 0.0},   // positive x*y: sigma_xy > 0
      {120, 3.0, 0.0, 0.0},  // negative x*y: sigma_xy < 0
      {60, 9.7, 0.0, 0.0},   // offset near L_x: grain 1 at x = 0.225 (wrapped)
      {30, 6.2, 0.8, 0.3},   // sheared, with a dashpot: the affine flow across the boundary
  };
  for (const Case& c : cases) {
    CAPTURE(c.theta_deg);
    CAPTURE(c.offset);
    CAPTURE(c.rate);
    const double th = c.theta_deg * pi / 180, nx = std::cos(th), ny = std::sin(th);
    const double dx = dist * nx, dy = dist * ny;
    const double x1 = std::fmod(1 - dx + c.offset, 10.0), y1 = 0.2 - dy + 10;
    std::string text = scene;
    text.replace(text.find("KEY"), 3, "rate");
    auto sim = test::simulation_from(test::fill(text, {{"value", c.rate}, {"zeta", c.zeta}, {"x1", x1}, {"y1", y1}}));
    State& s = sim->state();
    s.box.le_offset = c.offset;
    s.le_displacement = c.offset;
    sim->prepare();  // lists and forces at t = 0, no motion
    const auto contacts = touching_contacts(s);
    REQUIRE(contacts.size() == 1);
    // Normal force: spring, and the dashpot on the normal relative velocity, which is the
    // affine flow difference across the boundary gd d_y along x (the grains are at rest
    // relative to the flow): v_n = gd d_y n_x > 0 for th = 30 deg, the grains separate.
    const double c_n = 2 * c.zeta * std::sqrt(m_eff * k);
    const double fn = k * overlap - c_n * (c.rate * dy * nx);
    const double f0[2] = {fn * nx, fn * ny};  // force on grain 0 (i = 0 < j = 1)
    const double d0[2] = {dx, dy};
    REQUIRE(contacts[0].i == 0);
    CHECK(contacts[0].fn == doctest::Approx(fn).epsilon(1e-12));
    const Measurements meas = measure(sim->model(), s);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        CAPTURE(a);
        CAPTURE(b);
        CHECK(meas.stress[a][b] == doctest::Approx(f0[a] * d0[b] / V).epsilon(1e-12));
      }
    CHECK(meas.stress[0][1] == doctest::Approx(meas.stress[1][0]).epsilon(1e-12));  // central force
    // Compression positive; sigma_xy has the sign of n_x n_y (a contact pushing the grains apart
    // along a direction with positive x*y components gives sigma_xy > 0).
    CHECK(meas.stress[0][0] > 0);
    CHECK(meas.stress[1][1] > 0);
    CHECK((meas.stress[0][1] > 0) == (nx * ny > 0));
    CHECK(test::observe(sim->model(), s, "stress.xy") == doctest::Approx(fn * nx * dy / V).epsilon(1e-12));
    CHECK(test::observe(sim->model(), s, "mu") == doctest::Approx(std::abs(nx / ny)).epsilon(1e-12));
    // Fabric <n n> of the single contact, and the fluctuating energy of grains at rest.
    CHECK(test::observe(sim->model(), s, "fabric.xx") == doctest::Approx(nx * nx).epsilon(1e-12));
    CHECK(test::observe(sim->model(), s, "fabric.xy") == doctest::Approx(nx * ny).epsilon(1e-12));
    CHECK(test::observe(sim->model(), s, "fabric.yy") == doctest::Approx(ny * ny).epsilon(1e-12));
    CHECK(test::observe(sim->model(), s, "ke_fluct") == 0);
  }
  {  // the stress-controlled shear reads tau = -sigma_xy of the same contact
    const double th = 60 * pi / 180, dx = dist * std::cos(th), dy = dist * std::sin(th), off = 4.4;
    std::string text = scene;
    text.replace(text.find("KEY"), 3, "stress");
    auto sim = test::simulation_from(
        test::fill(text, {{"value", 0.1}, {"zeta", 0.0}, {"x1", 1 - dx + off}, {"y1", 10.2 - dy}}));
    State& s = sim->state();
    s.box.le_offset = off;
    s.le_displacement = off;
    sim->prepare();
    const double sxy = k * overlap * std::cos(th) * dy / V;
    CHECK(measure(sim->model(), s).stress[0][1] == doctest::Approx(sxy).epsilon(1e-12));
    CHECK(s.shear_stress == doctest::Approx(-sxy).epsilon(1e-12));
  }
}
