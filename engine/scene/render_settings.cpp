// [render] of a scene -> RenderSettings (the renderer draws from these; no GL in the engine).
#include <algorithm>
#include <cmath>
#include <string>

#include "scene/render_settings.hpp"

namespace silt {

bool RenderSettings::wants(const std::string& item) const {
  return std::find(draw.begin(), draw.end(), item) != draw.end();
}

namespace scene {

void read_render_settings(const SceneDesc& d, Model& m) {
  RenderSettings& r = m.render;
  const int D = m.dim;
  r.width = static_cast<int>(d.integer("render.width"));
  r.height = static_cast<int>(d.integer("render.height"));
  if (static_cast<int64_t>(r.width) * r.height > RenderSettings::kMaxPixels)
    d.fail(d.has("render.width") ? "render.width" : "render.height",
           "render.width x render.height = " + std::to_string(r.width) + " x " + std::to_string(r.height) + " = " +
               std::to_string(static_cast<int64_t>(r.width) * r.height / 1000000) +
               " Mpx is above the limit of 64 Mpx (8192 x 8192; a frame needs about 16 bytes per pixel)");
  r.draw = d.strings("render.draw");
  // Unset: speed, or flat when chains or a field are drawn (the renderer decides, so that
  // `render FILE chains` in the shell gets the force-chain picture too).
  r.color_by = d.has("render.color_by") ? d.string("render.color_by") : "";
  r.colormap = d.string("render.colormap");
  if (r.color_by == "vz" && D == 2) d.fail("render.color_by", "vz does not exist in 2D (use vy)");
  if (d.has("render.range")) {
    const auto v = d.reals("render.range");
    if (v.size() != 2 || !(v[1] > v[0])) d.fail("render.range", "needs [lo, hi] with hi > lo");
    r.range_auto = false;
    r.range[0] = v[0];
    r.range[1] = v[1];
  }
  auto rgb = [&](const char* key, double* out) {
    const auto v = d.reals(key);
    if (v.size() != 3) d.fail(key, "needs 3 entries (red, green, blue in [0, 1])");
    std::copy(v.begin(), v.end(), out);
  };
  rgb("render.flat_color", r.flat_color);
  rgb("render.background", r.background);
  r.chain_width = d.real("render.chain_width");
  r.chains_above_mean = d.boolean("render.chains_above_mean");
  r.slab_half_width = D == 3 ? d.real("render.slab_half_width") : 0.0;
  for (int k = 0; k < 3; ++k) r.slab_center[k] = k < D ? m.box.lo[k] + 0.5 * m.box.len[k] : 0.0;
  auto vec = [&](const char* key, double* out) {
    const auto v = d.reals(key);
    if (static_cast<int>(v.size()) != D) d.fail(key, "needs " + std::to_string(D) + " entries");
    for (int k = 0; k < 3; ++k) out[k] = k < D ? v[k] : 0.0;
  };
  if (d.has("render.slab_center")) vec("render.slab_center", r.slab_center);
  if (d.has("render.slab_normal")) vec("render.slab_normal", r.slab_normal);
  // Unset (-1): opaque, or 0.25 in 3D when chains are drawn (decided by the renderer).
  r.grain_opacity = d.has("render.grain_opacity") ? d.real("render.grain_opacity") : -1.0;
  r.field = d.string("render.field");
  if (d.has("render.field_range")) {
    const auto v = d.reals("render.field_range");
    if (v.size() != 2 || !(v[1] > v[0])) d.fail("render.field_range", "needs [lo, hi] with hi > lo");
    r.field_range_auto = false;
    r.field_range[0] = v[0];
    r.field_range[1] = v[1];
  }
  if (D == 3) {
    // The slice plane n . x = position, n a unit normal: along an axis, or any direction.
    double* n = r.slice_normal;
    if (d.has("render.slice_normal")) {
      if (d.has("render.slice_axis")) d.fail("render.slice_normal", "give render.slice_normal or render.slice_axis, not both");
      vec("render.slice_normal", n);
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > 0) || !std::isfinite(len)) d.fail("render.slice_normal", "needs a non-zero finite vector");
      for (int k = 0; k < 3; ++k) n[k] /= len;
    } else {
      const int axis = d.string("render.slice_axis")[0] - 'x';
      for (int k = 0; k < 3; ++k) n[k] = k == axis ? 1.0 : 0.0;
    }
    double centre = 0;
    for (int k = 0; k < 3; ++k) centre += n[k] * (m.box.lo[k] + 0.5 * m.box.len[k]);
    r.slice_position = d.has("render.slice_position") ? d.real("render.slice_position") : centre;
    r.slice_component = d.string("render.slice_component");
  } else {
    for (const char* k : {"render.slice_axis", "render.slice_normal", "render.slice_position", "render.slice_component",
                          "render.slab_center", "render.slab_normal", "render.slab_half_width"})
      if (d.has(k)) d.fail(k, std::string(k) + " applies to 3D scenes only");
  }
  r.azimuth = d.real("render.camera.azimuth");
  r.elevation = d.real("render.camera.elevation");
  r.distance = d.real("render.camera.distance");
  r.fov = d.real("render.camera.fov");
  if (d.has("render.camera.target")) {
    vec("render.camera.target", r.target);
    r.target_auto = false;
  }
  r.periodic_images = d.boolean("render.periodic_images");
  r.every = d.has("render.every") ? d.integer("render.every") : 0;
  // A fluid field needs the fluid module; this engine version has none.
  if (r.wants("field"))
    d.fail("render.draw", "'field' draws a fluid field (" + r.field + "), but this scene has no fluid module");
}

}  // namespace scene
}  // namespace silt
