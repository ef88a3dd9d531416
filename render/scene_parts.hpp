// The parts of build_render_scene (no GL), each in its own file.
#pragma once

#include <string>

#include "silt/render.hpp"

namespace silt::render {

// Force chains: a normal force F draws a capsule of width chain_width (F / <F>) r_mean, capped at
// one mean grain diameter, coloured by F / <F> through the sequential map saturating at this:
inline constexpr double kChainColorMax = 3.0;
inline constexpr double kChainMaxWidthRadii = 2.0;

// What a colour bar shows.
struct ColorScale {
  std::string colormap;
  double lo = 0, hi = 1;
  std::string label;
};

// Whether a point lies in the chain slab: within slab_half_width of the plane through slab_center
// normal to slab_normal (3D).
bool in_slab(const View& v, const std::array<float, 3>& x);

// One segment per contact carrying a normal force, between the centres; `lift` raises them along
// z (2D: in front of the disks). Returns the chains' colour scale.
ColorScale add_force_chains(RenderScene& rs, const State& s, const View& v, double r_mean, float lift);
// The lubrication forces of a paste (the field pair_f_lub), drawn apart from the contacts' chains:
// a thin segment between the centres of every connected pair, its width the normal lubrication
// force relative to the mean of its magnitudes, coloured by its sign on a diverging map
// (red: grains approaching, pushed apart; blue: separating, pulled together). Returns the scale;
// none (an empty label) when the scene has no lubrication.
ColorScale add_lubrication_chains(RenderScene& rs, const State& s, const View& v, double r_mean, float lift);

// The outline of the simulation box (as the state has it: controlled lengths follow): a rectangle
// at height z in 2D, its twelve edges in 3D. Under Lees-Edwards shear the box stays rectangular
// (the images are shifted, not the box): a tick on the upper edge marks the offset of the image
// above.
void add_box_outline(RenderScene& rs, const State& s, float z);

// A field drawn as a textured quad: in 2D, a map of the xy plane at height z; in 3D, the slice
// plane n . x = p (View::slice_normal, slice_position) sampled trilinearly. Returns its colour
// scale; adds a warning for NaN values or a slice that misses the grid.
ColorScale add_field(RenderScene& rs, const GridField& f, const View& v, int dim, float z, bool si_units = true);

}  // namespace silt::render
