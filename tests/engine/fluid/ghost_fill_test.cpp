// The ghost values of the padded arrays (fluid/boundaries.hpp) against their definition: along a
// periodic axis every ghost, corners and edges included, is the value of the position it wraps
// to; along a no-slip wall the tangential ghosts mirror the wall's velocity and the normal
// component vanishes on the wall. Grids large enough for the fills to be cut into several tasks.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fluid/boundaries.hpp"

using namespace silt::fluid;

namespace {

Grid ghost_grid(int dim, std::array<int64_t, 3> n, bool y_walls) {
  Grid g;
  g.dim = dim;
  g.n = n;
  if (dim == 2) g.n[2] = 1;
  if (y_walls)
    for (int side = 0; side < 2; ++side) {
      g.bc[1][side].type = BcType::kNoSlip;
      g.bc[1][side].velocity = {side == 1 ? 0.75 : 0.0, 0, 0};
    }
  return g;
}

// Arrays of the padded shape, every slot (ghosts too) random; NaN would hide a missed ghost
// behind a failing comparison as well, but a random value also catches a ghost copied from the
// wrong place.
std::vector<double> random_padded(const Layout& L, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::vector<double> v(static_cast<size_t>(L.size));
  for (double& x : v) x = uni(rng);
  return v;
}

// Over every padded position (-1 .. n + 1 on each axis): along each periodic axis b, a ghost
// (-1, n, n + 1) holds the value at its image (n - 1, 0, 1). Returns the number of mismatches.
int periodic_mismatches(const Grid& g, const Layout& L, const double* f) {
  int bad = 0;
  const int64_t k1 = g.dim == 3 ? g.n[2] + 1 : 0, k0 = g.dim == 3 ? -1 : 0;
  for (int64_t k = k0; k <= k1; ++k)
    for (int64_t j = -1; j <= g.n[1] + 1; ++j)
      for (int64_t i = -1; i <= g.n[0] + 1; ++i) {
        std::array<int64_t, 3> idx{i, j, k}, image = idx;
        bool ghost = false;
        for (int b = 0; b < g.dim; ++b) {
          if (!g.periodic(b)) continue;
          const int64_t n = g.n[b];
          if (idx[b] == -1) image[b] = n - 1;
          if (idx[b] >= n) image[b] = idx[b] - n;
          ghost = ghost || image[b] != idx[b];
        }
        if (ghost && f[L.at(i, j, k)] != f[L.at(image[0], image[1], image[2])]) ++bad;
      }
  return bad;
}

}  // namespace

TEST_CASE("ghost fills: periodic ghosts, corners included, are the values they wrap to") {
  struct Case {
    int dim;
    std::array<int64_t, 3> n;
    bool y_walls;
  };
  for (const Case& c : {Case{2, {37, 130, 1}, false}, Case{2, {130, 37, 1}, true}, Case{3, {9, 70, 33}, false},
                        Case{3, {40, 12, 70}, true}, Case{3, {2, 3, 2}, false}}) {
    CAPTURE(c.dim);
    CAPTURE(c.n[0]);
    CAPTURE(c.y_walls);
    const Grid g = ghost_grid(c.dim, c.n, c.y_walls);
    const Layout L(g);
    std::vector<double> u0 = random_padded(L, 1), u1 = random_padded(L, 2), u2 = random_padded(L, 3);
    std::vector<double> p = random_padded(L, 4);
    fill_velocity_ghosts(g, L, {u0.data(), u1.data(), u2.data()});
    fill_pressure_ghosts(g, L, p.data());
    CHECK(periodic_mismatches(g, L, u0.data()) == 0);
    CHECK(periodic_mismatches(g, L, u1.data()) == 0);
    if (c.dim == 3) CHECK(periodic_mismatches(g, L, u2.data()) == 0);
    CHECK(periodic_mismatches(g, L, p.data()) == 0);
    if (!c.y_walls) continue;
    // The walls along y, checked inside the box along x (and z): u (tangential) mirrors the
    // wall's velocity about the wall, v (normal) is zero on it, the pressure's gradient is zero.
    const int64_t ny = g.n[1];
    int bad = 0;
    for (int64_t k = 0; k < (c.dim == 3 ? g.n[2] : 1); ++k)
      for (int64_t i = 0; i < g.n[0]; ++i) {
        auto at = [&](int64_t j) { return L.at(i, j, k); };
        bad += std::abs(u0[at(-1)] + u0[at(0)] - 0.0) > 1e-15;
        bad += std::abs(u0[at(ny)] + u0[at(ny - 1)] - 1.5) > 1e-15;
        bad += u1[at(0)] != 0.0 || u1[at(ny)] != 0.0;
        bad += u1[at(-1)] != -u1[at(1)] || u1[at(ny + 1)] != -u1[at(ny - 1)];
        bad += p[at(-1)] != p[at(0)] || p[at(ny)] != p[at(ny - 1)];
      }
    CHECK(bad == 0);
  }
}
