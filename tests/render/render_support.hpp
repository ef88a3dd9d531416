// Helpers of the renderer's tests: views, pixels of world points, colours.
#pragma once

#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/camera.hpp"
#include "silt/render.hpp"

namespace silt::test {

// Three disks in a row along x in an 8 x 4 box, pressed together: the left contact overlaps 4
// times as much as the right one.
inline const char* kRow = R"(
[scene]
dimension = 2
[domain]
lo = [0, 0]
hi = [8, 4]
[contact]
model = "linear"
k_n = 1000
[[grains]]
radius = 1.0
placement = "explicit"
positions = [[1.5, 2], [3.46, 2], [5.45, 2]]
[run]
dt = 1e-3
)";

inline bool white(render::Rgba c) { return c.r > 245 && c.g > 245 && c.b > 245; }

// The pixel (x, y from the top) that shows the world point (x, y, z).
inline std::array<int, 2> pixel_of(const render::RenderScene& rs, double x, double y, double z = 0) {
  const auto p = render::project(rs.camera, {x, y, z}, rs.width, rs.height);
  return {static_cast<int>(std::lround(p[0] - 0.5)), static_cast<int>(std::lround(p[1] - 0.5))};
}

inline render::Rgba pixel_at(const render::Image& img, const render::RenderScene& rs, double x, double y,
                             double z = 0) {
  const auto p = pixel_of(rs, x, y, z);
  return img.pixel(p[0], p[1]);
}

// Whether two colours agree within `tol` per channel.
inline bool near(render::Rgba a, render::Rgba b, int tol) {
  return std::abs(a.r - b.r) <= tol && std::abs(a.g - b.g) <= tol && std::abs(a.b - b.b) <= tol;
}

inline render::View plain_view(int w, int h, std::vector<std::string> draw) {
  render::View v;
  v.width = w;
  v.height = h;
  v.draw = std::move(draw);
  return v;
}

}  // namespace silt::test
