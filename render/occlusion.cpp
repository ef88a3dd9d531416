// Occlusion culling on a coarse grid of screen tiles (2 x 2 pixels), in the spirit of hierarchical
// depth buffers but on the CPU and conservative by construction.
//
// Opaque spheres are taken from the nearest to the farthest. A sphere is hidden when every tile
// its screen rectangle touches is already covered, at a distance from the eye below the sphere's
// nearest point, by a nearer opaque sphere. A sphere that is drawn then covers the tiles lying
// wholly inside its silhouette (the four corner rays of the tile pass within r of its centre; the
// silhouette is convex), at the distance |c| of its centre: along any ray inside the silhouette
// the visible front of the sphere is nearer than that (its points facing the eye satisfy
// |p|^2 < p . c, so |p| < |c|). Distances are from the eye, along each ray, so "nearer" means the
// same thing for the covering sphere and the covered one. Chains are tested the same way with the
// box bounding them, and so are translucent spheres; neither covers anything.
#include "render/occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace silt::render {
namespace {

constexpr int kTile = 2;

struct Eye {
  const Camera& c;
  int width, height;

  std::array<double, 3> of(const std::array<float, 3>& p) const {
    std::array<double, 3> e{};
    for (int r = 0; r < 3; ++r) e[r] = c.view[r] * p[0] + c.view[4 + r] * p[1] + c.view[8 + r] * p[2] + c.view[12 + r];
    return e;
  }
  // Pixel (x, y from the top) of an eye-space point in front of the eye.
  std::array<double, 2> pixel(const std::array<double, 3>& e) const {
    const float* m = c.proj.data();
    const double w = -e[2];
    const double x = (m[0] * e[0] + m[8] * e[2]) / w, y = (m[5] * e[1] + m[9] * e[2]) / w;
    return {(x + 1) * 0.5 * width, (1 - y) * 0.5 * height};
  }
  // Unit direction of the ray through the pixel point (x, y), in eye space.
  std::array<double, 3> ray(double x, double y) const {
    const float* m = c.proj.data();
    const double nx = 2 * x / width - 1, ny = 1 - 2 * y / height;
    std::array<double, 3> d{(nx + m[8]) / m[0], (ny + m[9]) / m[5], -1.0};
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + 1.0);
    for (double& v : d) v /= n;
    return d;
  }
};

// The tiles touched by the projection of the eye-space box [lo, hi]; false if part of it is not
// in front of the eye (never culled then).
bool tile_rect(const Eye& eye, const std::array<double, 3>& lo, const std::array<double, 3>& hi, int nx, int ny,
               int r[4]) {
  if (hi[2] > -1e-6 * (std::abs(lo[2]) + 1)) return false;
  double x0 = 1e308, x1 = -1e308, y0 = 1e308, y1 = -1e308;
  for (int k = 0; k < 8; ++k) {
    const auto p = eye.pixel({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
    x0 = std::min(x0, p[0]);
    x1 = std::max(x1, p[0]);
    y0 = std::min(y0, p[1]);
    y1 = std::max(y1, p[1]);
  }
  if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1))) return false;
  // Clamped before the conversion: a box far outside the view projects beyond any int.
  auto tile = [](double v, int first, int last) {
    return static_cast<int>(std::clamp(std::floor(v / kTile), static_cast<double>(first), static_cast<double>(last)));
  };
  r[0] = tile(x0, 0, nx);
  r[1] = tile(x1, -1, nx - 1);
  r[2] = tile(y0, 0, ny);
  r[3] = tile(y1, -1, ny - 1);
  return true;
}

}  // namespace

Hidden find_hidden(const RenderScene& scene) {
  Hidden h{std::vector<char>(scene.spheres.size(), 0), std::vector<char>(scene.segments.size(), 0)};
  if (scene.camera.ortho || scene.spheres.empty()) return h;
  const Eye eye{scene.camera, scene.width, scene.height};
  const int nx = (scene.width + kTile - 1) / kTile, ny = (scene.height + kTile - 1) / kTile;
  std::vector<double> cover(static_cast<size_t>(nx) * ny, 1e308);  // distance covered up to
  // Hidden when every touched tile is covered nearer than `nearest`, with a margin for the depth
  // buffer's resolution.
  auto hidden = [&](const int r[4], double nearest) {
    const double limit = nearest * (1 - 1e-4);
    for (int ty = r[2]; ty <= r[3]; ++ty)
      for (int tx = r[0]; tx <= r[1]; ++tx)
        if (!(cover[static_cast<size_t>(ty) * nx + tx] < limit)) return false;
    return true;
  };
  struct Item {
    std::array<double, 3> e;
    double r, nearest;
    size_t index;
  };
  std::vector<Item> items;
  items.reserve(scene.spheres.size());
  for (size_t k = 0; k < scene.spheres.size(); ++k) {
    const auto& s = scene.spheres[k];
    const auto e = eye.of(s.centre);
    items.push_back({e, s.radius, std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) - s.radius, k});
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.nearest < b.nearest; });
  std::vector<char> inside;
  for (const Item& it : items) {
    int r[4];
    const std::array<double, 3> lo{it.e[0] - it.r, it.e[1] - it.r, it.e[2] - it.r},
        hi{it.e[0] + it.r, it.e[1] + it.r, it.e[2] + it.r};
    if (!tile_rect(eye, lo, hi, nx, ny, r)) continue;
    if (hidden(r, it.nearest)) {
      h.spheres[it.index] = 1;
      continue;
    }
    if (scene.spheres[it.index].color.a != 255 || r[1] < r[0] || r[3] < r[2]) continue;
    // Which tile corners see the sphere, then the tiles whose four corners all do.
    const int cw = r[1] - r[0] + 2, ch = r[3] - r[2] + 2;
    inside.assign(static_cast<size_t>(cw) * ch, 0);
    for (int j = 0; j < ch; ++j)
      for (int i = 0; i < cw; ++i) {
        const auto d = eye.ray((r[0] + i) * kTile, (r[2] + j) * kTile);
        const double along = d[0] * it.e[0] + d[1] * it.e[1] + d[2] * it.e[2];
        const double off2 = it.e[0] * it.e[0] + it.e[1] * it.e[1] + it.e[2] * it.e[2] - along * along;
        inside[static_cast<size_t>(j) * cw + i] = along > 0 && off2 < it.r * it.r;
      }
    const double dist = it.nearest + it.r;
    for (int j = 0; j + 1 < ch; ++j)
      for (int i = 0; i + 1 < cw; ++i) {
        const char* row = &inside[static_cast<size_t>(j) * cw + i];
        if (row[0] && row[1] && row[cw] && row[cw + 1]) {
          double& c = cover[static_cast<size_t>(r[2] + j) * nx + r[0] + i];
          c = std::min(c, dist);
        }
      }
  }
  // Chains: the eye-space box around both end spheres; its nearest point to the eye.
  for (size_t k = 0; k < scene.segments.size(); ++k) {
    const auto& s = scene.segments[k];
    const auto a = eye.of(s.a), b = eye.of(s.b);
    const double rad = 0.5 * s.width;
    std::array<double, 3> lo{}, hi{};
    double n2 = 0;
    for (int m = 0; m < 3; ++m) {
      lo[m] = std::min(a[m], b[m]) - rad;
      hi[m] = std::max(a[m], b[m]) + rad;
      const double q = std::clamp(0.0, lo[m], hi[m]);
      n2 += q * q;
    }
    int r[4];
    if (tile_rect(eye, lo, hi, nx, ny, r) && hidden(r, std::sqrt(n2))) h.segments[k] = 1;
  }
  return h;
}

}  // namespace silt::render
