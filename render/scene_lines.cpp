// Force chains and the box outline of a frame (no GL).
#include <algorithm>
#include <cmath>

#include "render/scene_parts.hpp"
#include "silt/contacts.hpp"

namespace silt::render {

bool in_slab(const View& v, const std::array<float, 3>& x) {
  double off = 0, nn = 0;
  for (int a = 0; a < 3; ++a) {
    off += (x[a] - v.slab_center[a]) * v.slab_normal[a];
    nn += v.slab_normal[a] * v.slab_normal[a];
  }
  return std::abs(off) <= v.slab_half_width * std::sqrt(nn);
}

// The standard force-chain picture (Radjai et al. 1998, PRL 80, 61): a segment between the
// centres of every pair in contact, its width proportional to the normal force relative to the
// mean. Proportional up to a mean grain diameter, that is to F / <F> = 2 / chain_width (5 with the
// default 0.4, far in the exponential tail of the force distribution), where wider lines would
// only hide their neighbours.
ColorScale add_force_chains(RenderScene& rs, const State& s, const View& v, double r_mean, float lift) {
  const int D = s.dim;
  struct Chain {
    std::array<float, 3> a, b;
    double fn;
  };
  std::vector<Chain> contacts;
  double sum = 0;
  for_each_contact(s, [&](const Contact& k) {
    if (!(k.fn > 0)) return;
    Chain c{{0, 0, 0}, {0, 0, 0}, k.fn};
    for (int a = 0; a < D; ++a) {
      c.a[a] = static_cast<float>(s.particle_x[D * k.i + a]);
      c.b[a] = static_cast<float>(s.particle_x[D * k.i + a] - k.d[a]);  // the image of j next to i
    }
    if (D == 3 && v.slab_half_width > 0 &&
        !in_slab(v, {0.5f * (c.a[0] + c.b[0]), 0.5f * (c.a[1] + c.b[1]), 0.5f * (c.a[2] + c.b[2])}))
      return;
    contacts.push_back(c);
    sum += k.fn;
  });
  // No contact, no scale: the bar goes to what else is drawn (the lubrication's forces) or none.
  if (contacts.empty()) return {};
  const double mean = sum / static_cast<double>(contacts.size());
  const Colormap& cm = Colormap::get("sequential");
  rs.segments.reserve(rs.segments.size() + contacts.size());
  for (const Chain& c : contacts) {
    const double rel = c.fn / mean;
    if (v.chains_above_mean && rel <= 1) continue;
    const float width = static_cast<float>(std::min(v.chain_width * rel, kChainMaxWidthRadii) * r_mean);
    RenderScene::Segment seg{c.a, c.b, width, cm.at(rel / kChainColorMax)};
    seg.a[2] += lift;
    seg.b[2] += lift;
    rs.segments.push_back(seg);
  }
  return {"sequential", 0.0, kChainColorMax, "normal force / mean"};
}

ColorScale add_lubrication_chains(RenderScene& rs, const State& s, const View& v, double r_mean, float lift) {
  const FieldInfo* field = find_field("pair_f_lub");
  const int D = s.dim;
  if (!field) return {};
  const auto f = double_field(s, field->id);
  if (f.size() != static_cast<size_t>(D * s.n_pairs())) return {};
  struct Link {
    std::array<float, 3> a, b;
    double fn;
  };
  std::vector<Link> links;
  double sum = 0;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      double d[3] = {0, 0, 0}, dist2 = 0, fd = 0;
      for (int a = 0; a < D; ++a) d[a] = s.particle_x[D * i + a] - s.particle_x[D * s.pair_j[p] + a];
      s.box.nearest(d, D);
      for (int a = 0; a < D; ++a) {
        dist2 += d[a] * d[a];
        fd += f[D * p + a] * d[a];
      }
      if (fd == 0 || dist2 == 0) continue;
      Link l{{0, 0, 0}, {0, 0, 0}, fd / std::sqrt(dist2)};
      for (int a = 0; a < D; ++a) {
        l.a[a] = static_cast<float>(s.particle_x[D * i + a]);
        l.b[a] = static_cast<float>(s.particle_x[D * i + a] - d[a]);
      }
      if (D == 3 && v.slab_half_width > 0 &&
          !in_slab(v, {0.5f * (l.a[0] + l.b[0]), 0.5f * (l.a[1] + l.b[1]), 0.5f * (l.a[2] + l.b[2])}))
        continue;
      links.push_back(l);
      sum += std::abs(l.fn);
    }
  const double mean = links.empty() ? 1.0 : sum / static_cast<double>(links.size());
  const Colormap& cm = Colormap::get("diverging");
  for (const Link& l : links) {
    const double rel = l.fn / mean;
    // Half the contacts' width: the two networks stay apart in one picture.
    const float width = static_cast<float>(0.5 * std::min(v.chain_width * std::abs(rel), kChainMaxWidthRadii) * r_mean);
    RenderScene::Segment seg{l.a, l.b, width, cm.at(0.5 + 0.5 * std::clamp(rel / kChainColorMax, -1.0, 1.0))};
    seg.a[2] += lift;
    seg.b[2] += lift;
    rs.segments.push_back(seg);
  }
  return {"diverging", -kChainColorMax, kChainColorMax, "lubrication force / mean"};
}

void add_box_outline(RenderScene& rs, const State& s, float z) {
  const int D = s.dim;
  const bool dark = rs.background.r + rs.background.g + rs.background.b < 384;
  const Rgba ink = dark ? Rgba{220, 220, 220, 255} : Rgba{40, 40, 40, 255};
  constexpr float kWidthPx = 2;
  const Box& b = s.box;
  auto corner = [&](int c) {
    std::array<float, 3> x{0, 0, z};
    for (int k = 0; k < D; ++k) x[k] = static_cast<float>(b.lo[k] + ((c >> k) & 1) * b.len[k]);
    return x;
  };
  for (int c = 0; c < (1 << D); ++c)
    for (int k = 0; k < D; ++k)
      if (!((c >> k) & 1)) rs.lines.push_back({corner(c), corner(c | (1 << k)), kWidthPx, ink});
  if (b.lees_edwards) {
    // Where the origin of the image one period up lands on the upper face: x = lo + offset.
    std::array<float, 3> a = corner(2), e = corner(2);
    a[0] = e[0] = static_cast<float>(b.lo[0] + b.le_offset);
    if (D == 2) {
      a[1] -= static_cast<float>(0.03 * b.len[1]);
      e[1] += static_cast<float>(0.03 * b.len[1]);
    } else {
      e[2] = static_cast<float>(b.lo[2] + b.len[2]);
    }
    rs.lines.push_back({a, e, kWidthPx, ink});
  }
}

}  // namespace silt::render
