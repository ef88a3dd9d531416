// Cameras: an orthographic one framing a 2D domain, an orbit camera for 3D. Column-major 4x4
// matrices as OpenGL expects.
#include <cmath>

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
  const double t = 1.0 / std::tan(fovy_deg * 3.14159265358979323846 / 360.0);
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

}  // namespace

Camera frame_2d(const Box& box, const Margins& mg, int width, int height, double depth) {
  Camera c;
  c.ortho = true;
  const double w = width - mg.left - mg.right, h = height - mg.top - mg.bottom;
  const double s = std::min(w / box.len[0], h / box.len[1]);
  // Centre the domain in the free area; world extents of the whole image.
  const double px0 = mg.left + 0.5 * (w - s * box.len[0]);
  const double py0 = mg.bottom + 0.5 * (h - s * box.len[1]);  // from the bottom
  const double l = box.lo[0] - px0 / s, b = box.lo[1] - py0 / s;
  c.view = look_at(Vec3(0, 0, depth), Vec3(0, 0, 0), Vec3::UnitY());
  c.proj = ortho(l, l + width / s, b, b + height / s, 0.0, 2 * depth);
  c.eye = {0, 0, static_cast<float>(depth)};
  c.pixels_per_unit = s;
  c.domain_px = {static_cast<int>(std::floor(px0)), static_cast<int>(std::floor(py0)),
                 static_cast<int>(std::ceil(s * box.len[0])), static_cast<int>(std::ceil(s * box.len[1]))};
  return c;
}

Camera orbit_3d(const Vec3& target, double radius, double azimuth_deg, double elevation_deg, double distance,
                double fov_deg, int width, int height) {
  Camera c;
  c.ortho = false;
  const double deg = 3.14159265358979323846 / 180.0;
  const double half = 0.5 * fov_deg * deg;
  const double aspect = static_cast<double>(width) / height;
  // Auto framing: the bounding sphere fits the smaller of the two fields of view.
  const double fit = std::min(std::sin(half), std::sin(std::atan(std::tan(half) * aspect)));
  const double d = distance > 0 ? distance : 1.08 * radius / fit;
  const double az = azimuth_deg * deg, el = elevation_deg * deg;
  const Vec3 eye = target + d * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.view = look_at(eye, target, Vec3::UnitZ());
  const double near = std::max(1e-3 * d, d - 1.5 * radius), far = d + 1.5 * radius;
  c.proj = perspective(fov_deg, aspect, near, far);
  c.eye = {static_cast<float>(eye[0]), static_cast<float>(eye[1]), static_cast<float>(eye[2])};
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
