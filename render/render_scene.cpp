// build_render_scene: a Model, a State and a View -> the frame's content, with no GL.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/camera.hpp"
#include "silt/contacts.hpp"
#include "silt/render.hpp"

namespace silt::render {
namespace {

Rgba rgba_of(const double* c, double alpha = 1.0) {
  auto b = [](double x) { return static_cast<uint8_t>(std::lround(255 * std::clamp(x, 0.0, 1.0))); };
  return {b(c[0]), b(c[1]), b(c[2]), b(alpha)};
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// Value of the colouring quantity for grain i, and its label.
double grain_value(const View& v, const Model& m, const State& s, int64_t i) {
  const int D = m.dim;
  const double* vel = &s.particle_v[D * i];
  if (v.color_by == "speed") {
    double v2 = 0;
    for (int k = 0; k < D; ++k) v2 += vel[k] * vel[k];
    return std::sqrt(v2);
  }
  if (v.color_by == "vx") return vel[0];
  if (v.color_by == "vy") return vel[1];
  if (v.color_by == "vz") return vel[D - 1];
  if (v.color_by == "height") return s.particle_x[D * i + D - 1];
  if (v.color_by == "id") return s.particle_id[i];
  if (v.color_by == "group") return s.particle_group[i];
  return 0;
}

// Under Lees-Edwards shear the grains' velocities are stored relative to the shear flow, and
// drawn so: the fluctuations are what a picture of a homogeneous shear shows.
std::string quantity_label(const View& v, int dim, bool sheared) {
  const std::string rel = sheared ? " rel. to shear flow" : "";
  if (v.color_by == "speed") return "speed" + rel + " [m/s]";
  if (v.color_by == "vx") return "vx" + rel + " [m/s]";
  if (v.color_by == "vy") return "vy" + rel + " [m/s]";
  if (v.color_by == "vz") return (dim == 2 ? "vy" : "vz") + rel + std::string(" [m/s]");
  if (v.color_by == "height") return "height [m]";
  return v.color_by;
}

// A "nice" length (1, 2 or 5 times a power of ten) near `target`.
double nice_length(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (double f : {5.0, 2.0, 1.0})
    if (f * p <= target) return f * p;
  return p;
}

void add_field_2d(RenderScene& rs, const ScalarGrid& g, const View& v, float z) {
  RenderScene::FieldQuad q;
  q.tex_w = g.nx;
  q.tex_h = g.ny;
  double lo = v.field_range[0], hi = v.field_range[1];
  int64_t nans = 0;
  if (v.field_range_auto) {
    double mx = 0;
    for (double x : g.value) {
      if (std::isnan(x)) ++nans;
      else mx = std::max(mx, std::abs(x));
    }
    if (mx == 0) mx = 1;
    lo = -mx;
    hi = mx;
  } else {
    for (double x : g.value) nans += std::isnan(x);
  }
  const Colormap& cm = Colormap::get("diverging");
  q.texels.resize(g.value.size());
  for (size_t k = 0; k < g.value.size(); ++k) q.texels[k] = cm.at((g.value[k] - lo) / (hi - lo));
  const float x0 = static_cast<float>(g.lo[0]), y0 = static_cast<float>(g.lo[1]);
  const float x1 = static_cast<float>(g.lo[0] + g.nx * g.h[0]), y1 = static_cast<float>(g.lo[1] + g.ny * g.h[1]);
  q.corners = {{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}};
  rs.fields.push_back(std::move(q));
  if (nans)
    rs.warnings.push_back("field '" + g.name + "' has " + std::to_string(nans) + " NaN value(s), drawn grey");
  rs.colorbar.on = v.wants("colorbar");
  rs.colorbar.colormap = "diverging";
  rs.colorbar.lo = lo;
  rs.colorbar.hi = hi;
  rs.colorbar.label = g.name;
}

// 3D slice of a cell-centred grid through `position` along `axis`: a textured quad.
void add_field_slice(RenderScene& rs, const ScalarGrid& g, const View& v) {
  const int a = v.slice_axis[0] - 'x';
  const int u = (a + 1) % 3, w = (a + 2) % 3;
  const int n[3] = {g.nx, g.ny, g.nz};
  const int layer = std::clamp(static_cast<int>(std::floor((v.slice_position - g.lo[a]) / g.h[a])), 0, n[a] - 1);
  ScalarGrid s2;
  s2.name = g.name;
  s2.nx = n[u];
  s2.ny = n[w];
  s2.value.resize(static_cast<size_t>(n[u]) * n[w]);
  for (int j = 0; j < n[w]; ++j)
    for (int i = 0; i < n[u]; ++i) {
      int idx[3];
      idx[a] = layer;
      idx[u] = i;
      idx[w] = j;
      s2.value[static_cast<size_t>(j) * n[u] + i] = g.at(idx[0], idx[1], idx[2]);
    }
  add_field_2d(rs, s2, v, 0);
  // Place the quad on the plane.
  auto& q = rs.fields.back();
  const double pos = v.slice_position;
  const double u0 = g.lo[u], u1 = g.lo[u] + n[u] * g.h[u], w0 = g.lo[w], w1 = g.lo[w] + n[w] * g.h[w];
  const double cu[4] = {u0, u1, u1, u0}, cw[4] = {w0, w0, w1, w1};
  for (int c = 0; c < 4; ++c) {
    q.corners[c][a] = static_cast<float>(pos);
    q.corners[c][u] = static_cast<float>(cu[c]);
    q.corners[c][w] = static_cast<float>(cw[c]);
  }
}

}  // namespace

RenderScene build_render_scene(const Model& m, const State& s, const View& v, const ScalarGrid* field) {
  if (v.width < 16 || v.height < 16 || v.width > 16384 || v.height > 16384)
    throw RenderError("image size " + std::to_string(v.width) + " x " + std::to_string(v.height) +
                      " is outside 16 .. 16384 pixels");
  const int D = m.dim;
  RenderScene rs;
  rs.width = v.width;
  rs.height = v.height;
  rs.background = rgba_of(v.background);
  const bool bar = v.wants("colorbar");
  Margins mg;
  if (bar) mg.right = 110;
  if (v.wants("time")) mg.top = 36;
  if (v.wants("scalebar")) mg.bottom = 40;
  double r_mean = 0;
  for (double r : s.particle_r) r_mean += r / std::max<int64_t>(1, s.n);
  const double r_max = s.n ? *std::max_element(s.particle_r.begin(), s.particle_r.end()) : 0.0;

  // Camera.
  if (D == 2) {
    rs.camera = frame_2d(s.box, mg, v.width, v.height, 10 * (r_max + 1e-300) + 1.0);
    const auto& d = rs.camera.domain_px;
    rs.clip = {d[0], d[1], d[2], d[3]};
  } else {
    Vec3 lo(s.box.lo[0], s.box.lo[1], s.box.lo[2]);
    Vec3 len(s.box.len[0], s.box.len[1], s.box.len[2]);
    Vec3 target = lo + 0.5 * len;
    if (!v.target_auto) target = Vec3(v.target[0], v.target[1], v.target[2]);
    rs.camera = orbit_3d(target, 0.5 * len.norm(), v.azimuth, v.elevation, v.distance, v.fov, v.width, v.height);
  }

  // Grains.
  const bool draw_field = v.wants("field") && field != nullptr;
  if (v.wants("field") && field == nullptr) rs.warnings.push_back("no field to draw in this scene");
  if (v.wants("grains") || (draw_field && D == 3)) {
    const bool colored = v.color_by != "flat" && v.color_by != "frozen";
    double lo = v.range[0], hi = v.range[1];
    if (colored && v.range_auto) {
      lo = 1e308;
      hi = -1e308;
      for (int64_t i = 0; i < s.n; ++i) {
        if (s.particle_frozen[i]) continue;
        const double x = grain_value(v, m, s, i);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      if (v.color_by == "speed") lo = 0;
      if (!(hi > lo)) hi = lo + 1;
    }
    const Colormap& cm = Colormap::get(v.colormap);
    const double alpha = v.grain_opacity > 0 ? v.grain_opacity : 1.0;
    const double frozen_rgb[3] = {0.45 * v.flat_color[0], 0.45 * v.flat_color[1], 0.45 * v.flat_color[2]};
    const int slice_axis = v.slice_axis[0] - 'x';
    for (int64_t i = 0; i < s.n; ++i) {
      Rgba c;
      if (s.particle_frozen[i]) c = rgba_of(frozen_rgb, alpha);
      else if (!colored) c = rgba_of(v.flat_color, alpha);
      else {
        c = cm.at((grain_value(v, m, s, i) - lo) / (hi - lo));
        c.a = static_cast<uint8_t>(std::lround(255 * alpha));
      }
      std::array<float, 3> x{0, 0, 0};
      for (int k = 0; k < D; ++k) x[k] = static_cast<float>(s.particle_x[D * i + k]);
      float radius = static_cast<float>(s.particle_r[i]);
      if (draw_field && D == 3) {
        // Only the grains cut by the slice, as their sections on it.
        const double dist = x[slice_axis] - v.slice_position;
        if (std::abs(dist) >= radius) continue;
        radius = static_cast<float>(std::sqrt(radius * radius - dist * dist));
        x[slice_axis] = static_cast<float>(v.slice_position);
      }
      rs.spheres.push_back({x, radius, c});
      if (v.periodic_images) {
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
            y[0] = static_cast<float>((mask & 1) ? shifted
                                                 : shifted - s.box.len[0] * std::floor((shifted - s.box.lo[0]) / s.box.len[0]));
          }
          if (crossing) rs.spheres.push_back({y, radius, c});
        }
      }
    }
    if (colored && bar && !draw_field) {
      rs.colorbar.on = true;
      rs.colorbar.colormap = v.colormap;
      rs.colorbar.lo = lo;
      rs.colorbar.hi = hi;
      rs.colorbar.label = quantity_label(v, D, m.shear.on);
    }
  }

  // Force chains: one segment per contact between the centres, width proportional to the normal
  // force relative to the mean, coloured by it (Radjai et al. 1998 style).
  if (v.wants("chains")) {
    struct Chain {
      std::array<float, 3> a, b;
      double fn;
    };
    std::vector<Chain> contacts;
    double sum = 0;
    for (const Contact& k : touching_contacts(s)) {
      if (!(k.fn > 0)) continue;
      Chain c{};
      for (int a = 0; a < D; ++a) {
        c.a[a] = static_cast<float>(s.particle_x[D * k.i + a]);
        c.b[a] = static_cast<float>(s.particle_x[D * k.i + a] - k.d[a]);
      }
      if (D == 3 && v.slab_half_width > 0) {
        double off = 0, nn = 0;
        for (int a = 0; a < 3; ++a) {
          off += (0.5 * (c.a[a] + c.b[a]) - v.slab_center[a]) * v.slab_normal[a];
          nn += v.slab_normal[a] * v.slab_normal[a];
        }
        if (std::abs(off) / std::sqrt(nn) > v.slab_half_width) continue;
      }
      c.fn = k.fn;
      contacts.push_back(c);
      sum += k.fn;
    }
    const double mean = contacts.empty() ? 1.0 : sum / contacts.size();
    const Colormap& cm = Colormap::get("sequential");
    // 2D: chains in front of the disks (the camera looks down -z).
    const float lift = D == 2 ? static_cast<float>(2 * r_max) : 0.0f;
    for (const Chain& c : contacts) {
      const double rel = c.fn / mean;
      if (v.chains_above_mean && rel <= 1) continue;
      const float width = static_cast<float>(std::min(1.0, v.chain_width * rel) * r_mean);  // at most a radius
      Rgba color = cm.at(std::min(1.0, rel / 3.0));
      RenderScene::Segment seg{c.a, c.b, width, color};
      seg.a[2] += lift;
      seg.b[2] += lift;
      rs.segments.push_back(seg);
    }
  }

  // Field: 2D map below the grains, or a 3D slice.
  if (draw_field) {
    if (D == 2) add_field_2d(rs, *field, v, static_cast<float>(-2 * r_max));
    else add_field_slice(rs, *field, v);
  }

  // Overlays.
  if (rs.colorbar.on) {
    rs.colorbar.x = v.width - 90;
    rs.colorbar.y = mg.top + 20;
    rs.colorbar.width = 18;
    rs.colorbar.height = std::max(20, v.height - mg.top - mg.bottom - 40);
  }
  const Rgba ink = (v.background[0] + v.background[1] + v.background[2]) > 1.5 ? Rgba{20, 20, 20, 255} : Rgba{235, 235, 235, 255};
  if (v.wants("time")) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "t = %.6g s    step %lld", s.t, static_cast<long long>(s.step));
    rs.texts.push_back({buf, 12, 24, 16, ink});
  }
  if (v.wants("scalebar") && rs.camera.ortho && rs.camera.pixels_per_unit > 0) {
    const double len = nice_length(0.2 * s.box.len[0]);
    rs.scalebar.on = true;
    rs.scalebar.width_px = static_cast<int>(std::lround(len * rs.camera.pixels_per_unit));
    rs.scalebar.x = 20;
    rs.scalebar.y = v.height - 22;
    rs.scalebar.label = number(len) + " m";
  }
  return rs;
}

Image render_frame(Rasterizer& r, const Model& m, const State& s, const View& v, const ScalarGrid* field) {
  const RenderScene rs = build_render_scene(m, s, v, field);
  Image img = r.draw(rs);
  compose_overlays(rs, img);
  return img;
}

}  // namespace silt::render
