// Cameras: an orthographic one framing a 2D domain, an orbit camera for 3D. Column-major 4x4
// matrices as OpenGL expects.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/camera.hpp"

namespace silt::render {
namespace {

using M4 = std::array<float, 16>;

M4 ortho(double l, double r, double b, double t, double n, double f) {
  M4 m{};
  m[0] = static_cast<float>(2 / (r - l));
  m[5] = static_cast<float>(2 / (t - b));
  m[10] = static_cast<float>(-2 / (f - n));
  m[12] = static_cast<float>(-(r + l) / (r - l));
  m[13] = static_cast<float>(-(t + b) / (t - b));
  m[14] = static_cast<float>(-(f + n) / (f - n));
  m[15] = 1;
  return m;
}

M4 perspective(double fovy_deg, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fovy_deg * std::numbers::pi / 360.0);
  M4 m{};
  m[0] = static_cast<float>(t / aspect);
  m[5] = static_cast<float>(t);
  m[10] = static_cast<float>((f + n) / (n - f));
  m[11] = -1;
  m[14] = static_cast<float>(2 * f * n / (n - f));
  return m;
}

M4 look_at(const Vec3& eye, const Vec3& target, const Vec3& up_hint) {
  const Vec3 f = (target - eye).normalized();
  Vec3 up = up_hint;
  if (std::abs(f.dot(up)) > 0.999) up = Vec3::UnitY();
  const Vec3 s = f.cross(up).normalized();
  const Vec3 u = s.cross(f);
  M4 m{};
  for (int k = 0; k < 3; ++k) {
    m[4 * k + 0] = static_cast<float>(s[k]);
    m[4 * k + 1] = static_cast<float>(u[k]);
    m[4 * k + 2] = static_cast<float>(-f[k]);
  }
  m[12] = static_cast<float>(-s.dot(eye));
  m[13] = static_cast<float>(-u.dot(eye));
  m[14] = static_cast<float>(f.dot(eye));
  m[15] = 1;
  return m;
}

// The margins, or none along an axis where they would leave the domain no room (a frame too
// small for its overlays, which then lie over it): a negative room gave a negative scale, and the
// frame was drawn turned half a turn.
Margins fitting(Margins mg, int width, int height) {
  if (width - mg.left - mg.right < 1) mg.left = mg.right = 0;
  if (height - mg.top - mg.bottom < 1) mg.top = mg.bottom = 0;
  return mg;
}

}  // namespace

Camera frame_2d(const Box& state_box, const Margins& given, int width, int height, double depth) {
  const Margins mg = fitting(given, width, height);
  Camera c;
  c.ortho = true;
  const double w = width - mg.left - mg.right, h = height - mg.top - mg.bottom;
  // A box no frame can hold (a failed run's NaN, a length that is not positive, or one so small
  // or large that the scale is not a finite positive number) is framed as the unit square at the
  // origin: the frame still shows its time and bars, and nothing is converted from a NaN.
  Box box = state_box;
  const auto framable = [&](const Box& b) {
    const double sc = std::min(w / b.len[0], h / b.len[1]);
    return std::isfinite(b.lo[0]) && std::isfinite(b.lo[1]) && std::isfinite(sc) && sc > 0 &&
           std::isfinite(sc * b.len[0]) && std::isfinite(sc * b.len[1]);
  };
  if (!framable(box)) box.lo = {0, 0, 0}, box.len = {1, 1, 1};
  const double s = std::min(w / box.len[0], h / box.len[1]);
  // Centre the domain in the free area; world extents of the whole image.
  const double px0 = mg.left + 0.5 * (w - s * box.len[0]);
  const double py0 = mg.bottom + 0.5 * (h - s * box.len[1]);  // from the bottom
  const double l = box.lo[0] - px0 / s, b = box.lo[1] - py0 / s;
  c.view = look_at(Vec3(0, 0, depth), Vec3(0, 0, 0), Vec3::UnitY());
  c.proj = ortho(l, l + width / s, b, b + height / s, 0.0, 2 * depth);
  c.eye = {0, 0, static_cast<float>(depth)};
  c.pixels_per_unit = s;
  c.target = {box.lo[0] + 0.5 * box.len[0], box.lo[1] + 0.5 * box.len[1], 0};
  c.domain_px = {static_cast<int>(std::floor(px0)), static_cast<int>(std::floor(py0)),
                 static_cast<int>(std::ceil(s * box.len[0])), static_cast<int>(std::ceil(s * box.len[1]))};
  return c;
}

Camera orbit_3d(const Vec3& target, const std::vector<Vec3>& points, double azimuth_deg, double elevation_deg,
                double distance, double fov_deg, int width, int height, const Margins& given) {
  const Margins mg = fitting(given, width, height);
  Camera c;
  c.ortho = false;
  const double deg = std::numbers::pi / 180.0;
  const double t = 1.0 / std::tan(0.5 * fov_deg * deg);  // perspective scale: ndc_y = t y / depth
  const double aspect = static_cast<double>(width) / height;
  const double az = azimuth_deg * deg, el = elevation_deg * deg;
  const Vec3 back(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));  // target -> eye
  // The camera's axes, as look_at makes them.
  const Vec3 f = -back;
  const Vec3 up = std::abs(f.dot(Vec3::UnitZ())) > 0.999 ? Vec3::UnitY() : Vec3::UnitZ();
  const Vec3 right = f.cross(up).normalized(), upv = right.cross(f);
  // A point at (x, y, z) from the target in camera axes (z toward the eye) is at depth d - z, at
  // ndc (t / aspect) x / (d - z), t y / (d - z). Auto framing: the smallest d at which the points'
  // ndc spans fit kFill of the free area in both directions (bisection: the spans shrink as the
  // camera backs off; the upper bound keeps every point within kFill of the centre), then a
  // shift of the projection that centres them in it.
  const double fw = static_cast<double>(width - mg.left - mg.right) / width;
  const double fh = static_cast<double>(height - mg.top - mg.bottom) / height;
  constexpr double kFill = 0.96;
  std::vector<Vec3> cam;
  double upper = 0, nearest = -1e308, reach = 0;
  for (const Vec3& q : points) {
    const Vec3 r = q - target;
    cam.emplace_back(right.dot(r), upv.dot(r), back.dot(r));
    const Vec3& p = cam.back();
    upper =
        std::max(upper, p[2] + std::max(t / aspect * std::abs(p[0]) / (kFill * fw), t * std::abs(p[1]) / (kFill * fh)));
    nearest = std::max(nearest, p[2]);
    reach = std::max(reach, r.norm());
  }
  // ndc bounds {x0, x1, y0, y1} of the points seen from distance d.
  auto bounds = [&](double d) {
    std::array<double, 4> b{1e308, -1e308, 1e308, -1e308};
    for (const Vec3& p : cam) {
      const double x = t / aspect * p[0] / (d - p[2]), y = t * p[1] / (d - p[2]);
      b = {std::min(b[0], x), std::max(b[1], x), std::min(b[2], y), std::max(b[3], y)};
    }
    return b;
  };
  double d = distance, shift_x = 0, shift_y = 0;
  if (d <= 0 && upper > 0) {
    double lo = std::max(nearest, 0.0), hi = upper;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      const auto b = bounds(mid);
      const bool fits = mid > nearest && b[1] - b[0] <= 2 * kFill * fw && b[3] - b[2] <= 2 * kFill * fh;
      (fits ? hi : lo) = mid;
    }
    d = hi;
    const auto b = bounds(d);
    shift_x = -0.5 * (b[0] + b[1]);
    shift_y = -0.5 * (b[2] + b[3]);
  }
  if (d <= 0) d = 1.0;
  if (reach == 0) reach = 0.5 * d;
  const Vec3 eye = target + d * back;
  c.view = look_at(eye, target, Vec3::UnitZ());
  const double near = std::max(1e-3 * d, d - 1.5 * reach), far = d + 1.5 * reach;
  c.proj = perspective(fov_deg, aspect, near, far);
  // Shift in ndc (x_clip += cx w_clip) to the centre of the free area.
  const double cx = static_cast<double>(mg.left - mg.right) / width + shift_x;
  const double cy = static_cast<double>(mg.bottom - mg.top) / height + shift_y;
  for (int k = 0; k < 4; ++k) {
    c.proj[4 * k + 0] += static_cast<float>(cx * c.proj[4 * k + 3]);
    c.proj[4 * k + 1] += static_cast<float>(cy * c.proj[4 * k + 3]);
  }
  c.eye = {static_cast<float>(eye[0]), static_cast<float>(eye[1]), static_cast<float>(eye[2])};
  c.target = {target[0], target[1], target[2]};
  c.pixels_per_unit = 0.5 * t * height / d;
  return c;
}

std::array<double, 3> project(const Camera& c, const std::array<double, 3>& p, int width, int height) {
  double v[4] = {p[0], p[1], p[2], 1}, e[4] = {0, 0, 0, 0}, q[4] = {0, 0, 0, 0};
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) e[r] += c.view[4 * k + r] * v[k];
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) q[r] += c.proj[4 * k + r] * e[k];
  const double x = q[0] / q[3], y = q[1] / q[3];
  return {(x + 1) * 0.5 * width, (1 - y) * 0.5 * height, -e[2]};  // pixel x, pixel y from the top, view depth
}

}  // namespace silt::render
