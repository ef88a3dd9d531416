// [render] of a scene -> RenderSettings (the renderer draws from these; no GL in the engine).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "scene/core_module.hpp"
#include "scene/render_settings.hpp"
#include "silt/text.hpp"

namespace silt {

bool RenderSettings::wants(const std::string& item) const {
  return std::find(draw.begin(), draw.end(), item) != draw.end();
}

namespace scene {
namespace {

// A colour span hi - lo out of the doubles' range ([-1e308, 1e308]) maps every value to its lower
// end: a frame of one colour.
void check_span(const SceneDesc& d, const char* key, const std::vector<double>& v) {
  if (!std::isfinite(v[1] - v[0]))
    d.fail(key, "the span hi - lo = " + format_number(v[1] - v[0]) + " is not a finite number: give a narrower range");
}

// What frames show where the scene does not say: the grains, and a fluid's field under them (a
// fluid alone drew white frames, the grains it has none of and a speed colour bar).
std::vector<std::string> default_draw(const Model& m) {
  std::vector<std::string> draw;
  if (m.module_on("fluid")) draw.push_back("field");
  if (m.n_grains > 0 || draw.empty()) draw.push_back("grains");
  for (const char* item : {"colorbar", "time", "scalebar"}) draw.push_back(item);
  return draw;
}

}  // namespace

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
  r.draw = d.has("render.draw") ? d.strings("render.draw") : default_draw(m);
  // Unset: speed, or flat when chains or a field are drawn (the renderer decides, so that
  // `render FILE chains` in the shell gets the force-chain picture too).
  r.color_by = d.has("render.color_by") ? d.string("render.color_by") : "";
  r.colormap = d.string("render.colormap");
  if (r.color_by == "vz" && D == 2) d.fail("render.color_by", "vz does not exist in 2D (use vy)");
  if (d.has("render.range")) {
    const auto v = d.reals("render.range");
    if (v.size() != 2 || !(v[1] > v[0])) d.fail("render.range", "needs [lo, hi] with hi > lo");
    check_span(d, "render.range", v);
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
  if (d.has("render.slab_center")) {
    vec("render.slab_center", r.slab_center);
    r.slab_center_auto = false;
  }
  if (d.has("render.slab_normal")) {
    vec("render.slab_normal", r.slab_normal);
    // (a zero normal put every grain in the slab without a word)
    const double len = std::hypot(r.slab_normal[0], r.slab_normal[1], r.slab_normal[2]);
    if (!(len > 0) || !std::isfinite(len)) d.fail("render.slab_normal", "needs a non-zero finite vector");
    for (double& c : r.slab_normal) c /= len;  // (its squares' sum underflowed at [0, 1e-300, 0])
  }
  // Unset (-1): opaque, or 0.25 in 3D when chains are drawn (decided by the renderer).
  r.grain_opacity = d.has("render.grain_opacity") ? d.real("render.grain_opacity") : -1.0;
  r.field = d.string("render.field");
  if (d.has("render.field_range")) {
    const auto v = d.reals("render.field_range");
    if (v.size() != 2 || !(v[1] > v[0])) d.fail("render.field_range", "needs [lo, hi] with hi > lo");
    check_span(d, "render.field_range", v);
    r.field_range_auto = false;
    r.field_range[0] = v[0];
    r.field_range[1] = v[1];
  }
  if (D == 3) {
    // The slice plane n . x = position, n a unit normal: along an axis, or any direction.
    double* n = r.slice_normal;
    if (d.has("render.slice_normal")) {
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
    // A plane that misses the domain draws nothing but the box and the colour bar.
    const std::array<double, 2> span = m.box.span_along(n, 3);
    if (!(r.slice_position >= span[0] && r.slice_position <= span[1]))
      d.fail("render.slice_position", "the slice n . x = " + format_number(r.slice_position, 4) +
                                          " misses the domain, where n . x spans [" + format_number(span[0], 4) + ", " +
                                          format_number(span[1], 4) + "]");
    r.slice_component = d.string("render.slice_component");
  } else {
    // (the camera's keys too: accepted in 2D, they changed no pixel)
    for (const char* k :
         {"render.slice_axis", "render.slice_normal", "render.slice_position", "render.slice_component",
          "render.slab_center", "render.slab_normal", "render.slab_half_width", "render.camera.azimuth",
          "render.camera.elevation", "render.camera.distance", "render.camera.fov", "render.camera.target"})
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
  // (an empty list made every frame blank, where `render FILE []` is refused)
  if (r.draw.empty())
    d.fail("render.draw", "an empty list draws nothing: give what to draw (grains, chains, field, ...)");
  for (const std::string& item : r.draw)
    if (const std::string why = draw_refusal(m, item); !why.empty()) d.fail("render.draw", why);
  // (the keys of the fluid's field in a scene without one were taken and changed no pixel)
  if (!m.module_on("fluid"))
    for (const char* k : {"render.field", "render.field_range"})
      if (d.has(k)) d.fail(k, std::string(k) + " sets how a fluid's field is drawn, and this scene has no fluid");
  // A magnitude is drawn on a sequential map from 0 (a vorticity's [-5, 5] kept for |u| painted the
  // cavity one colour).
  const bool magnitude = r.field == "velocity" && (D == 2 || r.slice_component == "magnitude");
  if (magnitude && !r.field_range_auto && r.field_range[0] < 0)
    d.fail("render.field_range", "render.field_range starts at " + format_number(r.field_range[0], 4) +
                                     ", below 0, where |" + r.field +
                                     "| (a magnitude, drawn from 0) has no colour: give [0, hi] for it");
}

}  // namespace scene

std::string draw_refusal(const Model& m, const std::string& item) {
  if (item == "field" && !m.module_on("fluid"))
    return "'field' draws a fluid field (" + m.render.field + "), but this scene has no fluid module";
  if (item == "lubrication" && !m.module_on("paste"))
    return "'lubrication' draws a paste's lubrication forces, but this scene has no [lubrication]";
  return "";
}

namespace scene {
namespace {

std::vector<KeySpec> render_keys() {
  using K = KeyType;
  using S = std::vector<std::string>;
  // clang-format off
  std::vector<KeySpec> s = {
      // ---- render
      {"render.width", K::kInt, Value(int64_t{1280}), Range::closed(16, 16384), "px", false, {}, "Frame width (width x height at most 64 Mpx, e.g. 8192 x 8192)."},
      {"render.height", K::kInt, Value(int64_t{720}), Range::closed(16, 16384), "px", false, {}, "Frame height."},
      {"render.draw", K::kStringList, std::nullopt, Range::any(), "", true,
       S{"grains", "chains", "lubrication", "field", "colorbar", "time", "scalebar", "box"}, "What frames show (default: grains, colorbar, time, scalebar; with a fluid its field first, and no grains where there are none; lubrication: the lubrication forces of a paste, apart from the contacts' chains)."},
      {"render.color_by", K::kString, std::nullopt, Range::any(), "", true,
       S{"flat", "speed", "vx", "vy", "vz", "height", "id", "group", "frozen"}, "Quantity that colours the grains (default: speed, or flat when chains or a field are drawn)."},
      {"render.colormap", K::kString, Value(std::string("sequential")), Range::any(), "", true, S{"sequential", "diverging"}, "Colormap of the grains (assets/*.csv)."},
      {"render.range", K::kRealList, std::nullopt, Range::any(), "", true, {}, "Colour range [lo, hi] of the grain quantity (default: automatic)."},
      {"render.flat_color", K::kRealList, Value(std::vector<double>{0.75, 0.75, 0.78}), Range::closed(0, 1), "", true, {}, "RGB of grains when color_by = flat (and of frozen grains)."},
      {"render.background", K::kRealList, Value(std::vector<double>{1, 1, 1}), Range::closed(0, 1), "", true, {}, "RGB of the background."},
      {"render.chain_width", K::kReal, Value(0.4), Range::open_closed(0, 10), "", true, {}, "Force-chain width at the mean normal force, in mean grain radii; proportional to the force, at most a mean grain diameter."},
      {"render.chains_above_mean", K::kBool, Value(false), Range::any(), "", true, {}, "Draw only contacts carrying more than the mean normal force."},
      {"render.slab_half_width", K::kReal, Value(0.0), Range::non_negative(), "m", true, {}, "3D: draw only the chains and grains within this distance of the slab plane (0: all)."},
      {"render.slab_center", K::kRealList, std::nullopt, Range::any(), "m", true, {}, "3D: a point of the chain slab (default: domain centre)."},
      {"render.slab_normal", K::kRealList, std::nullopt, Range::any(), "", true, {}, "3D: normal of the chain slab (default: y)."},
      {"render.grain_opacity", K::kReal, std::nullopt, Range::open_closed(0, 1), "", true, {}, "Grain opacity (default: 1, or 0.25 in 3D with chains)."},
      {"render.field", K::kString, Value(std::string("vorticity")), Range::any(), "", true, S{"vorticity", "velocity", "pressure"}, "Fluid field drawn with draw = field."},
      {"render.field_range", K::kRealList, std::nullopt, Range::any(), "", true, {}, "Colour range of the field (default: symmetric about zero, from its extremes)."},
      {"render.slice_axis", K::kString, Value(std::string("z")), Range::any(), "", true, S{"x", "y", "z"}, "3D: normal of the field slice, along an axis."},
      {"render.slice_normal", K::kRealList, std::nullopt, Range::any(), "", true, {}, "3D: normal of the field slice, any direction (instead of slice_axis)."},
      {"render.slice_position", K::kReal, std::nullopt, Range::any(), "m", true, {}, "3D: the slice is the plane n . x = slice_position, n the unit normal (default: through the domain centre)."},
      {"render.slice_component", K::kString, Value(std::string("magnitude")), Range::any(), "", true, S{"x", "y", "z", "magnitude"}, "3D: component of a vector field on the slice."},
      {"render.camera.azimuth", K::kReal, Value(30.0), Range::closed(-360, 360), "deg", true, {}, "3D orbit camera: azimuth about z from +x."},
      {"render.camera.elevation", K::kReal, Value(25.0), Range::closed(-89, 89), "deg", true, {}, "3D orbit camera: elevation above the x-y plane."},
      {"render.camera.distance", K::kReal, Value(0.0), Range::non_negative(), "m", true, {}, "3D orbit camera: distance to the target (0: frame the domain)."},
      {"render.camera.target", K::kRealList, std::nullopt, Range::any(), "m", true, {}, "3D orbit camera: point looked at (default: domain centre)."},
      {"render.camera.fov", K::kReal, Value(30.0), Range::closed(1, 120), "deg", true, {}, "3D: vertical field of view."},
      {"render.periodic_images", K::kBool, Value(false), Range::any(), "", true, {}, "Also draw the periodic images of grains that cross the box."},
      {"render.every", K::kInt, std::nullopt, Range::closed(1, 1e12), "", true, {}, "Steps between frames (default: output.every)."},
  };
  // clang-format on
  for (KeySpec& k : s)
    if (k.path == "render.draw")
      k.computed = [](const Model& m) {
        std::string list;
        for (const std::string& item : m.render.draw) list += (list.empty() ? "" : ", ") + item;
        return list;
      };
  return s;
}

}  // namespace

const ModuleSpec& render_module() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "render";
    s.doc = "what frames show";
    s.keys = render_keys();
    s.rules = {KeyRule::one_of({{"render.slice_axis"}, {"render.slice_normal"}})};
    s.finish = read_render_settings;
    s.steer = [](Model& m, const Model& fresh) {
      m.render = fresh.render;
      return std::string();
    };
    return s;
  }();
  return spec;
}

}  // namespace scene

}  // namespace silt
