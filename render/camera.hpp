// Camera set-up (no GL): matrices for the rasterizer and projection for overlays and tests.
#pragma once

#include <array>

#include "silt/render.hpp"

namespace silt::render {

// Pixels kept free around a 2D domain for the overlays.
struct Margins {
  int left = 20, right = 20, top = 20, bottom = 20;
};

// Orthographic camera looking down -z at a 2D box, fitted into the image inside the margins.
Camera frame_2d(const Box& box, const Margins& margins, int width, int height, double depth);

// Perspective orbit camera about `target`; distance 0 frames a sphere of `radius`.
Camera orbit_3d(const Vec3& target, double radius, double azimuth_deg, double elevation_deg, double distance,
                double fov_deg, int width, int height);

// World point -> (pixel x, pixel y from the top, depth along the view direction).
std::array<double, 3> project(const Camera& c, const std::array<double, 3>& p, int width, int height);

}  // namespace silt::render
