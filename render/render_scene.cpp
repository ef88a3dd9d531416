// build_render_scene: a Model, a State and a View -> the frame's content, with no GL.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/camera.hpp"
#include "render/scene_parts.hpp"
#include "silt/module.hpp"

namespace silt::render {
namespace {

// A label's width in the overlays' font, or an estimate where the font cannot be read: the layout
// of a frame is built where nothing is drawn too (the shell's frames hook, the writer's sink),
// and an error of the font there escaped a background run.
int label_width(const std::string& text, int size) {
  try {
    return text_width(text, size);
  } catch (const RenderError&) {
    return static_cast<int>(text.size()) * size * 6 / 10;
  }
}

Rgba rgba_of(const double* c, double alpha = 1.0) {
  auto b = [](double x) { return static_cast<uint8_t>(std::lround(255 * std::clamp(x, 0.0, 1.0))); };
  return {b(c[0]), b(c[1]), b(c[2]), b(alpha)};
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// Value of the colouring quantity for grain i.
double grain_value(const std::string& color_by, int D, const State& s, int64_t i) {
  const double* vel = &s.particle_v[D * i];
  if (color_by == "speed") {
    double v2 = 0;
    for (int k = 0; k < D; ++k) v2 += vel[k] * vel[k];
    return std::sqrt(v2);
  }
  if (color_by == "vx") return vel[0];
  if (color_by == "vy") return vel[1];
  if (color_by == "vz") return vel[D - 1];
  if (color_by == "height") return s.particle_x[D * i + D - 1];
  if (color_by == "id") return s.particle_id[i];
  if (color_by == "group") return s.particle_group[i];
  return 0;
}

// Under Lees-Edwards shear the grains' velocities are stored relative to the shear flow, and
// drawn so: the fluctuations are what a picture of a homogeneous shear shows. A scene in reduced
// units has no SI unit to show.
std::string quantity_label(const std::string& color_by, int dim, bool sheared, bool reduced) {
  const std::string rel = sheared ? " rel. to shear flow" : "";
  const std::string speed = reduced ? "" : " [m/s]";
  if (color_by == "speed") return "speed" + rel + speed;
  if (color_by == "vx") return "vx" + rel + speed;
  if (color_by == "vy") return "vy" + rel + speed;
  if (color_by == "vz") return (dim == 2 ? "vy" : "vz") + rel + speed;
  if (color_by == "height") return reduced ? "height" : "height [m]";
  return color_by;
}

// A "nice" length (1, 2 or 5 times a power of ten) near `target`.
double nice_length(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (double f : {5.0, 2.0, 1.0})
    if (f * p <= target) return f * p;
  return p;
}

// The grains (disks in 2D), coloured by `color_by` and made translucent by `alpha`. With a 3D
// slice (`cut`), only the grains the plane cuts, as spheres of their section's radius centred on
// it. With a chain slab (3D, View::slab_half_width > 0), only the grains whose centres lie in it,
// so that its chains are not hidden. Returns the colour scale of a coloured quantity.
ColorScale add_grains(RenderScene& rs, const Model& m, const State& s, const View& v, const std::string& color_by,
                      double alpha, bool cut) {
  const int D = m.dim;
  const bool colored = color_by != "flat" && color_by != "frozen";
  ColorScale scale{v.colormap, v.range[0], v.range[1], quantity_label(color_by, D, m.shear.on, m.reduced_units)};
  if (colored && v.range_auto) {
    scale.lo = 1e308;
    scale.hi = -1e308;
    for (int64_t i = 0; i < s.n; ++i) {
      if (s.particle_frozen[i]) continue;
      const double x = grain_value(color_by, D, s, i);
      scale.lo = std::min(scale.lo, x);
      scale.hi = std::max(scale.hi, x);
    }
    if (scale.lo > scale.hi) scale.lo = 0, scale.hi = 1;  // no grain coloured (it read 1e308 to 1e308)
    if (color_by == "speed") scale.lo = 0;
    // A diverging map is white at 0 (a velocity component from -0.106 to 0.122 put white at 0.008).
    if (v.colormap == "diverging" && color_by != "speed") {
      const double most = std::max(std::abs(scale.lo), std::abs(scale.hi));
      scale.lo = -most;
      scale.hi = most;
    }
    // Every grain at one value: the middle of a range around it (hi = lo + 1 painted grains
    // falling at -0.0039 m/s the map's deep end, as if far below the rest).
    if (!(scale.hi > scale.lo)) {
      const double c = scale.lo, half = std::abs(c) > 0 ? std::abs(c) : 1.0;
      scale.lo = color_by == "speed" ? 0.0 : c - half;  // (grains at rest: the map's low end)
      scale.hi = c + half;
    }
  }
  const Colormap& cm = Colormap::get(v.colormap);
  const double frozen_rgb[3] = {0.45 * v.flat_color[0], 0.45 * v.flat_color[1], 0.45 * v.flat_color[2]};
  const double* n = v.slice_normal;
  for (int64_t i = 0; i < s.n; ++i) {
    Rgba c;
    if (s.particle_frozen[i]) c = rgba_of(frozen_rgb, alpha);
    else if (!colored) c = rgba_of(v.flat_color, alpha);
    else {
      c = cm.at((grain_value(color_by, D, s, i) - scale.lo) / (scale.hi - scale.lo));
      c.a = static_cast<uint8_t>(std::lround(255 * alpha));
    }
    std::array<float, 3> x{0, 0, 0};
    for (int k = 0; k < D; ++k) x[k] = static_cast<float>(s.particle_x[D * i + k]);
    float radius = static_cast<float>(s.particle_r[i]);
    if (D == 3 && v.slab_half_width > 0 && !in_slab(v, x)) continue;
    if (cut) {
      const double dist = n[0] * x[0] + n[1] * x[1] + n[2] * x[2] - v.slice_position;
      if (std::abs(dist) >= radius) continue;
      radius = static_cast<float>(std::sqrt(radius * radius - dist * dist));
      for (int k = 0; k < 3; ++k) x[k] = static_cast<float>(x[k] - dist * n[k]);
    }
    rs.spheres.push_back({x, radius, c});
    if (!v.periodic_images) continue;
    // Images of grains that cross a periodic boundary (one shift per direction and their
    // combinations), so that they are drawn whole on both sides.
    for (int mask = 1; mask < (1 << D); ++mask) {
      std::array<float, 3> y = x;
      bool crossing = true;
      for (int k = 0; k < D && crossing; ++k) {
        if (!(mask & (1 << k))) continue;
        if (!s.box.periodic[k]) crossing = false;
        else if (x[k] - radius < s.box.lo[k]) y[k] += static_cast<float>(s.box.len[k]);
        else if (x[k] + radius > s.box.lo[k] + s.box.len[k]) y[k] -= static_cast<float>(s.box.len[k]);
        else crossing = false;
      }
      // Under Lees-Edwards shear the image one period up is shifted along x by the offset.
      if (crossing && s.box.lees_edwards && (mask & 2) && y[1] != x[1]) {
        const double shifted = y[0] + (y[1] > x[1] ? 1.0 : -1.0) * s.box.le_offset;
        // Back into the box along x, unless this is also the image across x.
        y[0] = static_cast<float>(
            (mask & 1) ? shifted : shifted - s.box.len[0] * std::floor((shifted - s.box.lo[0]) / s.box.len[0]));
      }
      if (crossing) rs.spheres.push_back({y, radius, c});
    }
  }
  return scale;
}

// What a 3D camera frames by default: the domain, less the empty space above the grains (against
// gravity, along the axis nearest to it, when not periodic) if it is more than a tenth of that
// length, as the empty top of a chute. With the box outline or a field drawn, the whole domain.
std::vector<Vec3> frame_corners(const Model& m, const State& s, bool whole_domain, Vec3& centre) {
  Vec3 lo(s.box.lo[0], s.box.lo[1], s.box.lo[2]);
  Vec3 hi = lo + Vec3(s.box.len[0], s.box.len[1], s.box.len[2]);
  int up = 0;
  m.gravity.cwiseAbs().maxCoeff(&up);
  if (!whole_domain && s.n > 0 && m.gravity.norm() > 0 && !s.box.periodic[up]) {
    const double sign = m.gravity[up] < 0 ? 1.0 : -1.0;  // +1: up is +axis
    double top = -1e308;
    for (int64_t i = 0; i < s.n; ++i) top = std::max(top, sign * s.particle_x[3 * i + up] + s.particle_r[i]);
    double& side = sign > 0 ? hi[up] : lo[up];
    const double bottom = sign > 0 ? lo[up] : -hi[up];  // in the signed coordinate
    if (top > bottom && top - bottom < 0.9 * (hi[up] - lo[up])) side = sign * top;
  }
  centre = 0.5 * (lo + hi);
  std::vector<Vec3> corners;
  for (int c = 0; c < 8; ++c) corners.emplace_back(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]);
  return corners;
}

}  // namespace

RenderScene build_render_scene(const Model& m, const State& s, const View& given, const GridField* field) {
  // The chains' slab centred on the box as it is now: a stress-controlled box shrinks (centred on
  // the scene's, the slab sat at 64 % of the compressed box's height).
  View v = given;
  if (v.slab_center_auto)
    for (int k = 0; k < m.dim; ++k) v.slab_center[k] = s.box.lo[k] + 0.5 * s.box.len[k];
  // The field to draw, when none is given: the module's field of that name (a fluid's).
  std::vector<GridField> fields;
  if (field == nullptr && v.wants("field")) {
    fields = module_grid_fields(m, s, v.field);
    for (const GridField& f : fields)
      if (f.name == v.field) field = &f;
  }
  if (v.width < 16 || v.height < 16 || v.width > 16384 || v.height > 16384)
    throw RenderError("image size " + std::to_string(v.width) + " x " + std::to_string(v.height) +
                      " is outside 16 .. 16384 pixels");
  if (static_cast<int64_t>(v.width) * v.height > RenderSettings::kMaxPixels)
    throw RenderError("image size " + std::to_string(v.width) + " x " + std::to_string(v.height) +
                      " is above the limit of 64 Mpx (8192 x 8192)");
  const int D = m.dim;
  RenderScene rs;
  rs.width = v.width;
  rs.height = v.height;
  rs.background = rgba_of(v.background);

  // What is drawn, and which colour scale the bar shows: the field's, else the grains' quantity,
  // else the chains' force.
  const bool chains = v.wants("chains");
  const bool lubrication = v.wants("lubrication");
  const bool draw_field = v.wants("field") && field != nullptr;
  const std::string color_by =
      !v.color_by.empty() ? v.color_by : (chains || lubrication || draw_field ? "flat" : "speed");
  const double alpha = v.grain_opacity > 0 ? v.grain_opacity : (D == 3 && chains ? 0.25 : 1.0);
  if (v.wants("field") && field == nullptr) rs.warnings.push_back("no field to draw in this scene");
  const bool grains = v.wants("grains") || (draw_field && D == 3);
  const bool colored = grains && color_by != "flat" && color_by != "frozen";
  enum class Bar { kNone, kField, kGrains, kChains, kLubrication };
  Bar bar = !v.wants("colorbar") ? Bar::kNone
            : draw_field         ? Bar::kField
            : colored            ? Bar::kGrains
            : chains             ? Bar::kChains
            : lubrication        ? Bar::kLubrication
                                 : Bar::kNone;
  double r_mean = 0;
  for (double r : s.particle_r) r_mean += r / std::max<int64_t>(1, s.n);
  const double r_max = s.n ? *std::max_element(s.particle_r.begin(), s.particle_r.end()) : 0.0;

  // Content, before the camera (none of it depends on it): the margins follow what was drawn. In
  // 2D, from back to front along z: the field, the disks, the chains, the box.
  ColorScale scale, lubrication_scale;
  if (grains) {
    const ColorScale g = add_grains(rs, m, s, v, color_by, alpha, draw_field && D == 3);
    if (bar == Bar::kGrains) scale = g;
  }
  if (chains) {
    const ColorScale c = add_force_chains(rs, s, v, r_mean, D == 2 ? static_cast<float>(2 * r_max) : 0.0f);
    if (bar == Bar::kChains) scale = c;
    // (with no contact the bar showed the chains' scale over the lubrication's forces alone)
    if (bar == Bar::kChains && c.colormap.empty() && lubrication) bar = Bar::kLubrication;
  }
  if (lubrication) {
    // Below the contacts' chains in 2D.
    const ColorScale c = add_lubrication_chains(rs, s, v, r_mean, D == 2 ? static_cast<float>(1.5 * r_max) : 0.0f);
    if (c.label.empty()) rs.warnings.push_back("no lubrication forces to draw in this scene");
    else if (bar == Bar::kLubrication) scale = c;
    else lubrication_scale = c;
  }
  if (draw_field) {
    const ColorScale f = add_field(rs, *field, v, D, static_cast<float>(-2 * r_max), !m.reduced_units);
    if (bar == Bar::kField) scale = f;
  }
  if (v.wants("box")) add_box_outline(rs, s, D == 2 ? static_cast<float>(4 * r_max) : 0.0f);
  // No bar where what it was for has nothing drawn (lubrication in a dry state).
  if (scale.colormap.empty()) bar = Bar::kNone;

  // The bar is drawn in a margin of its own: a frame too narrow to keep the domain beside it has
  // none (it was drawn over the grains, the margin given up for the domain). Chains and
  // lubrication drawn together have a bar each, the lubrication's left of the chains' (only the
  // chains' was drawn, and the lubrication forces' colours could not be read).
  constexpr int kBarMargin = 110, kLeastDomain = 100;
  bool lubrication_bar = bar == Bar::kChains && !lubrication_scale.colormap.empty();
  if (lubrication_bar && v.width < 2 * kBarMargin + kLeastDomain) {
    rs.warnings.push_back("a frame " + std::to_string(v.width) +
                          " px wide has room for one colour bar, the chains': the lubrication forces' needs " +
                          std::to_string(2 * kBarMargin + kLeastDomain) + " px");
    lubrication_bar = false;
  }
  if (bar != Bar::kNone && v.width < kBarMargin + kLeastDomain) {
    rs.warnings.push_back("a frame " + std::to_string(v.width) + " px wide has no colour bar (it needs " +
                          std::to_string(kBarMargin + kLeastDomain) + " px)");
    bar = Bar::kNone;
  }
  Margins mg;
  if (bar != Bar::kNone) mg.right = kBarMargin * (lubrication_bar ? 2 : 1);
  // The time and the step on one line, or on two where the frame is too narrow for one (the step
  // was cut off).
  std::vector<std::string> time_lines;
  if (v.wants("time")) {
    char t_text[64];
    std::snprintf(t_text, sizeof t_text, "t = %.6g%s", s.t, m.reduced_units ? "" : " s");
    const std::string step_text = "step " + std::to_string(s.step);
    const std::string one = std::string(t_text) + "    " + step_text;
    time_lines = label_width(one, 16) <= v.width - 24 ? std::vector<std::string>{one}
                                                      : std::vector<std::string>{t_text, step_text};
    mg.top = 16 + 20 * static_cast<int>(time_lines.size());
  }
  if (v.wants("scalebar")) mg.bottom = 40;

  // Camera.
  if (D == 2) {
    rs.camera = frame_2d(s.box, mg, v.width, v.height, 10 * (r_max + 1e-300) + 1.0);
    const auto& d = rs.camera.domain_px;
    rs.clip = {d[0], d[1], d[2], d[3]};
  } else {
    Vec3 target;
    const std::vector<Vec3> corners = frame_corners(m, s, v.wants("box") || draw_field, target);
    if (!v.target_auto) target = Vec3(v.target[0], v.target[1], v.target[2]);
    rs.camera = orbit_3d(target, corners, v.azimuth, v.elevation, v.distance, v.fov, v.width, v.height, mg);
  }

  // Overlays. Two bars' labels, wider than the bars are apart, one above the other: the bars start
  // lower.
  constexpr int kLabelStep = 16;
  const int bar_top = mg.top + 20 + (lubrication_bar ? kLabelStep : 0);
  const int bar_height = std::max(20, v.height - bar_top - mg.bottom - 20);
  if (lubrication_bar) {
    const ColorScale& c = lubrication_scale;
    rs.lubrication_bar = {
        true, v.width - 90 - kBarMargin, bar_top, 18, bar_height, c.colormap, c.lo, c.hi, c.label, 8 + kLabelStep};
  }

  if (bar != Bar::kNone)
    rs.colorbar = {true, v.width - 90, bar_top, 18, bar_height, scale.colormap, scale.lo, scale.hi, scale.label};
  const Rgba ink =
      (v.background[0] + v.background[1] + v.background[2]) > 1.5 ? Rgba{20, 20, 20, 255} : Rgba{235, 235, 235, 255};
  for (size_t k = 0; k < time_lines.size(); ++k)
    rs.texts.push_back({time_lines[k], 12, 24 + 20 * static_cast<int>(k), 16, ink});
  if (v.wants("scalebar") && rs.camera.pixels_per_unit > 0) {
    // 2D: a fifth of the box. 3D: lengths at the target's depth (in the plane through it facing
    // the camera), about a sixth of the width seen there; also in 2D when a fifth of the box is
    // not in the frame (a box the frame could not hold is framed as the unit square, camera.cpp,
    // and its fifth could be billions of pixels).
    const double free_width = (v.width - mg.left - mg.right) / rs.camera.pixels_per_unit;
    double target = D == 2 ? 0.2 * s.box.len[0] : free_width / 6;
    if (!(target > 0 && target <= free_width)) target = free_width / 6;
    const double len = nice_length(target);
    if (!(std::isfinite(len) && len > 0)) return rs;
    rs.scalebar.on = true;
    rs.scalebar.width_px = static_cast<int>(std::lround(len * rs.camera.pixels_per_unit));
    rs.scalebar.x = 20;
    rs.scalebar.y = v.height - 22;
    rs.scalebar.label = number(len) + (m.reduced_units ? "" : " m") + (D == 3 ? " at the target" : "");
  }
  return rs;
}

Image render_frame(Rasterizer& r, const Model& m, const State& s, const View& v, const GridField* field) {
  const RenderScene rs = build_render_scene(m, s, v, field);
  Image img = r.draw(rs);
  compose_overlays(rs, img);
  return img;
}

}  // namespace silt::render
