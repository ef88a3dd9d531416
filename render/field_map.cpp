// Fields as textured quads: the map of a 2D field, or a slice plane of any normal through a 3D
// one, coloured by a diverging map symmetric about zero (signed quantities) or a sequential map
// from zero (magnitudes).
#include <algorithm>
#include <cmath>

#include "render/scene_parts.hpp"

namespace silt::render {

GridField field_component(const GridField& f, const std::string& which) {
  if (f.components == 1) return f;
  if (f.components != 3)
    throw RenderError("field '" + f.name + "' has " + std::to_string(f.components) + " components (1 or 3)");
  const int c = which == "x" ? 0 : which == "y" ? 1 : which == "z" ? 2 : which == "magnitude" ? 3 : -1;
  if (c < 0) throw RenderError("unknown field component '" + which + "' (x, y, z or magnitude)");
  GridField g = f;
  g.components = 1;
  g.name = c == 3 ? "|" + f.name + "|" : f.name + "_" + which;
  const size_t cells = f.value.size() / 3;
  g.value.resize(cells);
  for (size_t k = 0; k < cells; ++k) {
    const double* w = &f.value[3 * k];
    g.value[k] = c < 3 ? w[c] : std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  }
  return g;
}

namespace {

// A cell-centred scalar field at x, interpolated trilinearly between the cell centres and constant
// from the outermost centres to the grid's faces. `inside` is false off the grid. Corners of zero
// weight are skipped, so that a sample at a cell centre is that cell's value even next to a NaN.
double sample(const GridField& g, const Vec3& x, bool& inside) {
  const int n[3] = {g.nx, g.ny, g.nz};
  int i0[3], i1[3];
  double f[3];
  for (int k = 0; k < 3; ++k) {
    const double q = (x[k] - g.lo[k]) / g.h[k];  // in cells from the lower face
    if (!(q > -1e-9 && q < n[k] + 1e-9)) {
      inside = false;
      return 0;
    }
    const double c = std::clamp(q - 0.5, 0.0, n[k] - 1.0);
    i0[k] = static_cast<int>(c);
    i1[k] = std::min(i0[k] + 1, n[k] - 1);
    f[k] = c - i0[k];
  }
  inside = true;
  double v = 0;
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1;
    int idx[3];
    for (int k = 0; k < 3; ++k) {
      const bool up = corner & (1 << k);
      w *= up ? f[k] : 1 - f[k];
      idx[k] = up ? i1[k] : i0[k];
    }
    if (w > 0) v += w * g.at(idx[0], idx[1], idx[2]);
  }
  return v;
}

// The plane n . x = p through the grid's box: its extent [u0, u1] x [w0, w1] in the in-plane
// basis (u, w), from the points where the box's twelve edges cross it. False if it misses.
bool plane_extent(const GridField& g, const Vec3& n, double p, const Vec3& u, const Vec3& w, double ext[4]) {
  const int n_cells[3] = {g.nx, g.ny, g.nz};
  auto corner = [&](int c) {
    Vec3 x;
    for (int k = 0; k < 3; ++k) x[k] = g.lo[k] + ((c >> k) & 1) * n_cells[k] * g.h[k];
    return x;
  };
  ext[0] = ext[2] = 1e308;
  ext[1] = ext[3] = -1e308;
  bool hit = false;
  auto add = [&](const Vec3& x) {
    ext[0] = std::min(ext[0], x.dot(u));
    ext[1] = std::max(ext[1], x.dot(u));
    ext[2] = std::min(ext[2], x.dot(w));
    ext[3] = std::max(ext[3], x.dot(w));
    hit = true;
  };
  for (int c = 0; c < 8; ++c)
    for (int k = 0; k < 3; ++k) {
      if ((c >> k) & 1) continue;  // each edge once, from its lower end
      const Vec3 a = corner(c), b = corner(c | (1 << k));
      const double sa = n.dot(a) - p, sb = n.dot(b) - p;
      if (sa == 0) add(a);
      if (sb == 0) add(b);
      if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) add(a + sa / (sa - sb) * (b - a));
    }
  // A plane through a corner or along an edge, to round-off, cuts a sliver of 1e-16: no slice
  // (it drew a blank frame without a warning).
  const double sliver = 1e-9 * std::max({n_cells[0] * g.h[0], n_cells[1] * g.h[1], n_cells[2] * g.h[2]});
  return hit && ext[1] - ext[0] > sliver && ext[3] - ext[2] > sliver;
}

}  // namespace

ColorScale add_field(RenderScene& rs, const GridField& f, const View& v, int dim, float z, bool si_units) {
  const bool magnitude = f.components == 3 && v.slice_component == "magnitude";
  const GridField g = field_component(f, v.slice_component);
  // (a scene in reduced units had its bar labelled "vorticity [1/s]")
  ColorScale scale{magnitude ? "sequential" : "diverging", v.field_range[0], v.field_range[1],
                   g.unit.empty() || !si_units ? g.name : g.name + " [" + g.unit + "]"};
  int64_t nans = 0;
  double mx = 0;
  for (double x : g.value) {
    if (std::isnan(x)) ++nans;
    else mx = std::max(mx, std::abs(x));
  }
  if (v.field_range_auto) {
    if (!(mx > 0) || !std::isfinite(mx)) mx = 1;
    scale.lo = magnitude ? 0 : -mx;
    scale.hi = mx;
  }
  if (nans) rs.warnings.push_back("field '" + f.name + "' has " + std::to_string(nans) + " NaN value(s), drawn grey");
  const Colormap& cm = Colormap::get(scale.colormap);
  auto colour = [&](double x) { return cm.at((x - scale.lo) / (scale.hi - scale.lo)); };
  RenderScene::FieldQuad q;
  if (dim == 2) {
    // The cells themselves, one texel each.
    q.tex_w = g.nx;
    q.tex_h = g.ny;
    q.texels.resize(static_cast<size_t>(g.nx) * g.ny);
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) q.texels[g.cell(i, j)] = colour(g.at(i, j));
    const float x0 = static_cast<float>(g.lo[0]), y0 = static_cast<float>(g.lo[1]);
    const float x1 = static_cast<float>(g.lo[0] + g.nx * g.h[0]), y1 = static_cast<float>(g.lo[1] + g.ny * g.h[1]);
    q.corners = {{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}};
    rs.fields.push_back(std::move(q));
    return scale;
  }
  // 3D: an in-plane basis (u, w). Along an axis, the next two axes in cyclic order and one texel
  // per cell, texel centres on the cell centres; otherwise texels of half the smallest cell size
  // (the samples are interpolated: finer texels show it smoothly).
  Vec3 n(v.slice_normal[0], v.slice_normal[1], v.slice_normal[2]);
  n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
  int axis = -1;
  for (int k = 0; k < 3; ++k)
    if (std::abs(n[k]) > 1 - 1e-12) axis = k;
  Vec3 u = Vec3::Zero(), w = Vec3::Zero();
  if (axis >= 0) {
    u[(axis + 1) % 3] = 1;
    w[(axis + 2) % 3] = 1;
  } else {
    int k = 0;  // the axis least aligned with n
    n.cwiseAbs().minCoeff(&k);
    u = (Vec3::Unit(k) - n[k] * n).normalized();
    w = n.cross(u);
  }
  const double p = v.slice_position;
  double ext[4];
  if (!plane_extent(g, n, p, u, w, ext)) {
    rs.warnings.push_back("the slice plane misses the field '" + f.name + "'");
    return scale;
  }
  const double hmin = 0.5 * std::min({g.h[0], g.h[1], g.h[2]});
  const double su = axis >= 0 ? g.h[(axis + 1) % 3] : hmin, sw = axis >= 0 ? g.h[(axis + 2) % 3] : hmin;
  constexpr int kMaxTexels = 2048;  // per side
  q.tex_w = std::clamp(static_cast<int>(std::lround((ext[1] - ext[0]) / su)), 1, kMaxTexels);
  q.tex_h = std::clamp(static_cast<int>(std::lround((ext[3] - ext[2]) / sw)), 1, kMaxTexels);
  const double du = (ext[1] - ext[0]) / q.tex_w, dw = (ext[3] - ext[2]) / q.tex_h;
  q.texels.resize(static_cast<size_t>(q.tex_w) * q.tex_h);
  auto point = [&](double a, double b) -> Vec3 { return p * n + a * u + b * w; };
  for (int j = 0; j < q.tex_h; ++j)
    for (int i = 0; i < q.tex_w; ++i) {
      bool inside = false;
      const double x = sample(g, point(ext[0] + (i + 0.5) * du, ext[2] + (j + 0.5) * dw), inside);
      Rgba c = colour(x);
      if (!inside) c.a = 0;
      q.texels[static_cast<size_t>(j) * q.tex_w + i] = c;
    }
  const double cu[4] = {ext[0], ext[1], ext[1], ext[0]}, cw[4] = {ext[2], ext[2], ext[3], ext[3]};
  for (int c = 0; c < 4; ++c) {
    const Vec3 x = point(cu[c], cw[c]);
    q.corners[c] = {static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2])};
  }
  rs.fields.push_back(std::move(q));
  return scale;
}

}  // namespace silt::render
