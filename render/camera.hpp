// Camera set-up (no GL): matrices for the rasterizer and projection for overlays and tests.
#pragma once

#include <array>
#include <vector>

#include "silt/render.hpp"

namespace silt::render {

// Pixels kept free around a 2D domain for the overlays.
struct Margins {
  int left = 20, right = 20, top = 20, bottom = 20;
};

// Orthographic camera looking down -z at a 2D box, fitted into the image inside the margins.
Camera frame_2d(const Box& box, const Margins& margins, int width, int height, double depth);

// Perspective orbit camera about `target`, looking from azimuth and elevation (degrees) with a
// vertical field of view `fov_deg`. The projection is shifted so that the target lands at the
// centre of the area inside the margins; distance 0 frames `points` (e.g. the corners of a box)
// instead: the smallest distance at which they span 96 % of that area, centred in it.
Camera orbit_3d(const Vec3& target, const std::vector<Vec3>& points, double azimuth_deg, double elevation_deg,
                double distance, double fov_deg, int width, int height, const Margins& margins);

// World point -> (pixel x, pixel y from the top, depth along the view direction).
std::array<double, 3> project(const Camera& c, const std::array<double, 3>& p, int width, int height);

}  // namespace silt::render
