// Radii, placement and initial velocities of the [[grains]] tables.
//
// All draws come from one seeded generator per table (scene.seed, table index), so a scene gives
// the same grains everywhere. Random placement is random sequential addition: each grain is
// tried at uniform positions until it overlaps neither a placed grain nor a wall.
#include "dem/grain_setup.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "core/rng.hpp"
#include "dem/module.hpp"
#include "io/checkpoint_file.hpp"
#include "silt/text.hpp"

namespace silt::dem {
namespace {

std::string key(int g, const char* leaf) { return "grains[" + std::to_string(g) + "]." + leaf; }

// A uniform hash grid over grain centres for overlap queries while placing. Cells are at least
// `cell` wide; in periodic directions their number divides the box length and indices wrap.
class PlacementGrid {
 public:
  PlacementGrid(const Model& m, double cell) : m_(m) {
    for (int k = 0; k < 3; ++k) {
      size_[k] = cell;
      wrap_[k] = 0;
      if (k < m.dim && m.box.periodic[k]) {
        // Bounded as a double before the conversion: a box far longer than its grains (refused
        // later if it does not fit) gets cells wider than `cell`, which only costs time.
        const double n = std::floor(m.box.len[k] / cell);
        wrap_[k] = std::isfinite(n) ? static_cast<int64_t>(std::clamp(n, 1.0, kMaxWrap)) : 1;
        size_[k] = m.box.len[k] / wrap_[k];
      }
    }
  }
  void insert(int64_t i, const double* x) {
    int64_t c[3];
    cell_of(x, c);
    cells_[pack(c)].push_back(i);
  }
  // Largest overlap (as a fraction of the smaller radius) of a grain at x with radius r against
  // the grains already inserted; returns the partner index through `who`.
  double worst_overlap(const double* x, double r, const std::vector<double>& xs, const std::vector<double>& rs,
                       int64_t* who = nullptr) const {
    const int D = m_.dim;
    int64_t c[3];
    cell_of(x, c);
    // The neighbouring cells' keys, each once (a periodic direction of one or two cells wraps
    // onto itself), on the stack: this runs for every trial position of every grain.
    std::array<uint64_t, 27> keys;
    int nkeys = 0;
    const int zr = D == 3 ? 1 : 0;
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int64_t n[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
          for (int k = 0; k < 3; ++k)
            if (wrap_[k]) n[k] = ((n[k] % wrap_[k]) + wrap_[k]) % wrap_[k];
          keys[nkeys++] = pack(n);
        }
    std::sort(keys.begin(), keys.begin() + nkeys);
    nkeys = static_cast<int>(std::unique(keys.begin(), keys.begin() + nkeys) - keys.begin());
    double worst = 0;
    for (int q = 0; q < nkeys; ++q) {
      auto it = cells_.find(keys[q]);
      if (it == cells_.end()) continue;
      for (int64_t j : it->second) {
        double d2 = 0;
        for (int k = 0; k < D; ++k) {
          double d = x[k] - xs[D * j + k];
          if (m_.box.periodic[k]) d -= m_.box.len[k] * std::nearbyint(d / m_.box.len[k]);
          d2 += d * d;
        }
        const double gap = std::sqrt(d2) - r - rs[j];
        if (gap < 0) {
          const double f = -gap / std::min(r, rs[j]);
          if (f > worst) {
            worst = f;
            if (who) *who = j;
          }
        }
      }
    }
    return worst;
  }

 private:
  void cell_of(const double* x, int64_t* c) const {
    for (int k = 0; k < 3; ++k) {
      c[k] = 0;
      if (k >= m_.dim) continue;
      // Clamped: a coordinate far outside the domain (refused later) must not overflow; cells
      // are hashed modulo 2^21 anyway.
      const double f = std::floor((x[k] - m_.box.lo[k]) / size_[k]);
      c[k] = std::isfinite(f) ? static_cast<int64_t>(std::clamp(f, -1e15, 1e15)) : 0;
      if (wrap_[k]) c[k] = ((c[k] % wrap_[k]) + wrap_[k]) % wrap_[k];
    }
  }
  static uint64_t pack(const int64_t* c) {
    return (static_cast<uint64_t>(c[0] & 0x1FFFFF)) | (static_cast<uint64_t>(c[1] & 0x1FFFFF) << 21) |
           (static_cast<uint64_t>(c[2] & 0x1FFFFF) << 42);
  }
  static constexpr double kMaxWrap = 1 << 20;  // below the 21 bits a cell index keeps in pack()
  const Model& m_;
  double size_[3];
  int64_t wrap_[3];
  std::unordered_map<uint64_t, std::vector<int64_t>> cells_;
};

struct Group {
  std::string name;
  std::string placement;
  int64_t count = 0;
  std::vector<double> radius;
  std::vector<double> sites;   // lattice or explicit centres (D per grain)
  std::vector<double> lo, hi;  // region
  double density = 1;
  bool frozen = false;
};

void region_of(const SceneDesc& d, const Model& m, int g, Group& G) {
  G.lo.assign(m.box.lo.begin(), m.box.lo.begin() + m.dim);
  G.hi.resize(m.dim);
  for (int k = 0; k < m.dim; ++k) G.hi[k] = m.box.lo[k] + m.box.len[k];
  if (d.has(key(g, "region_lo"))) G.lo = d.reals(key(g, "region_lo"));
  if (d.has(key(g, "region_hi"))) G.hi = d.reals(key(g, "region_hi"));
  if (static_cast<int>(G.lo.size()) != m.dim)
    d.fail(key(g, "region_lo"), "needs " + std::to_string(m.dim) + " entries");
  if (static_cast<int>(G.hi.size()) != m.dim)
    d.fail(key(g, "region_hi"), "needs " + std::to_string(m.dim) + " entries");
  for (int k = 0; k < m.dim; ++k)
    if (!(G.hi[k] > G.lo[k])) d.fail(key(g, "region_hi"), "region_hi must exceed region_lo in every direction");
  // Grains live in the domain: the region is its intersection with it.
  for (int k = 0; k < m.dim; ++k) {
    G.lo[k] = std::max(G.lo[k], m.box.lo[k]);
    G.hi[k] = std::min(G.hi[k], m.box.lo[k] + m.box.len[k]);
    if (!(G.hi[k] > G.lo[k]))
      d.fail(key(g, "region_hi"), "the region does not meet the domain along " + std::string(1, "xyz"[k]));
  }
}

// Lattice sites in the half-open region [lo, hi). As with LAMMPS's `lattice`, sites sit at
// origin + integer multiples of the cell (origin: grains[].lattice_origin, default 0), so that
// several regions share one lattice.
std::vector<double> lattice_sites(const SceneDesc& d, const Model& m, int g, const Group& G) {
  const std::string kind = d.string(key(g, "lattice"));
  const double a = d.real(key(g, "spacing"));
  const int D = m.dim;
  if (kind == "hex" && D != 2) d.fail(key(g, "lattice"), "'hex' is the 2D triangular lattice; use 'fcc' in 3D");
  if (kind == "fcc" && D != 3) d.fail(key(g, "lattice"), "'fcc' is a 3D lattice; use 'hex' in 2D");
  // Basis of a conventional cell and its edge lengths.
  std::vector<std::array<double, 3>> basis;
  std::array<double, 3> cell{a, a, a};
  if (kind == "sc") {
    basis = {{0, 0, 0}};
  } else if (kind == "hex") {
    cell = {a, a * std::sqrt(3.0), a};
    basis = {{0, 0, 0}, {0.5 * a, 0.5 * a * std::sqrt(3.0), 0}};
  } else {  // fcc with nearest-neighbour distance a
    const double c = a * std::sqrt(2.0);
    cell = {c, c, c};
    basis = {{0, 0, 0}, {c / 2, c / 2, 0}, {c / 2, 0, c / 2}, {0, c / 2, c / 2}};
  }
  std::vector<double> origin(D, 0.0);
  if (d.has(key(g, "lattice_origin"))) origin = d.reals(key(g, "lattice_origin"));
  if (static_cast<int>(origin.size()) != D) d.fail(key(g, "lattice_origin"), "needs " + std::to_string(D) + " entries");
  // The cells to scan, counted in floating point first: a tiny spacing must not overflow them.
  double cells = static_cast<double>(basis.size());
  for (int k = 0; k < D; ++k) cells *= std::ceil((G.hi[k] - G.lo[k]) / cell[k]) + 3;
  if (!(cells <= 200'000'000))
    d.fail(key(g, "spacing"), "lattice spacing too small for the region (more than 2e8 sites to scan)");
  check_memory(d, m, static_cast<int64_t>(cells), key(g, "spacing"));
  int64_t first[3] = {0, 0, 0}, n[3] = {1, 1, 1};
  for (int k = 0; k < D; ++k) {
    first[k] = static_cast<int64_t>(std::floor((G.lo[k] - origin[k]) / cell[k])) - 1;
    n[k] = static_cast<int64_t>(std::ceil((G.hi[k] - G.lo[k]) / cell[k])) + 3;
  }
  std::vector<double> sites;
  for (int64_t iz = 0; iz < n[2]; ++iz)
    for (int64_t iy = 0; iy < n[1]; ++iy)
      for (int64_t ix = 0; ix < n[0]; ++ix)
        for (const auto& b : basis) {
          const int64_t idx[3] = {ix, iy, iz};
          double p[3];
          bool inside = true;
          for (int k = 0; k < D; ++k) {
            p[k] = origin[k] + (first[k] + idx[k]) * cell[k] + b[k];
            // Half-open with a tolerance so that sites on lo are in and sites on hi are out.
            const double tol = 1e-9 * a;
            if (p[k] < G.lo[k] - tol || p[k] >= G.hi[k] - tol) inside = false;
          }
          if (inside) sites.insert(sites.end(), p, p + D);
        }
  return sites;
}

std::vector<double> draw_radii(const SceneDesc& d, const Model& m, int g, int64_t count, Rng& rng) {
  const bool mono = d.has(key(g, "radius"));
  const bool uni = d.has(key(g, "radius_min")) || d.has(key(g, "radius_max"));
  const bool disc = d.has(key(g, "radii"));
  const bool list = d.has(key(g, "radius_list"));
  if (mono + uni + disc + list != 1)
    d.fail(key(g, "radius"), "grains[" + std::to_string(g) +
                                 "] needs exactly one of radius, radius_min/radius_max, radii with "
                                 "volume_fractions, or radius_list");
  std::vector<double> r;
  if (mono) {
    r.assign(count, d.real(key(g, "radius")));
  } else if (uni) {
    const double lo = d.real(key(g, "radius_min")), hi = d.real(key(g, "radius_max"));
    if (hi < lo) d.fail(key(g, "radius_max"), "radius_max is below radius_min");
    for (int64_t i = 0; i < count; ++i) r.push_back(rng.uniform(lo, hi));
  } else if (disc) {
    const auto sizes = d.reals(key(g, "radii"));
    const auto frac = d.reals(key(g, "volume_fractions"));
    if (frac.size() != sizes.size()) d.fail(key(g, "volume_fractions"), "needs one entry per radius in radii");
    const double total = std::accumulate(frac.begin(), frac.end(), 0.0);
    if (std::abs(total - 1) > 1e-9)
      d.fail(key(g, "volume_fractions"), "must add up to 1 (they add up to " + format_number(total) + ")");
    // Number fraction of size k is proportional to phi_k / r_k^D; largest-remainder rounding.
    std::vector<double> w(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) w[k] = frac[k] / std::pow(sizes[k], m.dim);
    const double wsum = std::accumulate(w.begin(), w.end(), 0.0);
    std::vector<int64_t> n(sizes.size());
    std::vector<std::pair<double, size_t>> rem;
    int64_t assigned = 0;
    for (size_t k = 0; k < sizes.size(); ++k) {
      const double exact = count * w[k] / wsum;
      n[k] = static_cast<int64_t>(std::floor(exact));
      assigned += n[k];
      rem.push_back({-(exact - n[k]), k});
    }
    std::sort(rem.begin(), rem.end());
    for (size_t q = 0; assigned < count; ++q, ++assigned) ++n[rem[q % rem.size()].second];
    for (size_t k = 0; k < sizes.size(); ++k) r.insert(r.end(), n[k], sizes[k]);
    for (int64_t i = count - 1; i > 0; --i) std::swap(r[i], r[rng.below(i + 1)]);
  } else {
    r = d.reals(key(g, "radius_list"));
    if (static_cast<int64_t>(r.size()) != count)
      d.fail(key(g, "radius_list"),
             "has " + std::to_string(r.size()) + " radii for " + std::to_string(count) + " grains");
  }
  return r;
}

// Group g's explicit positions, refused at their key when missing, empty, or not of dim
// coordinates each.
std::vector<std::vector<double>> explicit_positions(const SceneDesc& d, int g, int dim) {
  const auto pos = d.matrix(key(g, "positions"));
  for (const auto& p : pos)
    if (static_cast<int>(p.size()) != dim)
      d.fail(key(g, "positions"),
             "'" + key(g, "positions") + "': every position needs " + std::to_string(dim) + " coordinates");
  if (pos.empty()) d.fail(key(g, "positions"), "'" + key(g, "positions") + "': no positions given");
  return pos;
}

int64_t group_count(const SceneDesc& d, const Model& m, int g, Group& G) {
  const bool given = d.has(key(g, "count"));
  const int64_t count = given ? d.integer(key(g, "count")) : -1;
  if (G.placement == "lattice") {
    G.sites = lattice_sites(d, m, g, G);
    const int64_t n_sites = static_cast<int64_t>(G.sites.size()) / m.dim;
    if (n_sites == 0) d.fail(key(g, "spacing"), "the region holds no lattice site");
    if (count > n_sites) d.fail(key(g, "count"), "the lattice region holds only " + std::to_string(n_sites) + " sites");
    const int64_t n = given ? count : n_sites;
    G.sites.resize(n * m.dim);
    return n;
  }
  if (G.placement == "explicit") {
    const auto pos = explicit_positions(d, g, m.dim);
    for (const auto& p : pos) G.sites.insert(G.sites.end(), p.begin(), p.end());
    const int64_t n = static_cast<int64_t>(pos.size());
    if (given && count != n)
      d.fail(key(g, "count"),
             "count = " + std::to_string(count) + " but " + std::to_string(n) + " positions are given");
    return n;
  }
  if (given) return count;
  if (d.has(key(g, "radius_list"))) return static_cast<int64_t>(d.reals(key(g, "radius_list")).size());
  d.fail(key(g, "placement"), "random placement needs grains[" + std::to_string(g) + "].count");
}

void place_random(const SceneDesc& d, Model& m, int g, const Group& G, int64_t first, Rng& rng, PlacementGrid& grid) {
  const int D = m.dim;
  auto& xs = m.init.x;
  const auto& rs = m.init.radius;
  constexpr int kAttempts = 20000;
  std::vector<int> behind(m.walls.size());  // attempts a wall refused, the first that did
  for (int64_t q = 0; q < G.count; ++q) {
    const int64_t i = first + q;
    const double r = rs[i];
    double lo[3], hi[3];
    for (int k = 0; k < D; ++k) {
      const bool whole = m.box.periodic[k] && G.lo[k] <= m.box.lo[k] && G.hi[k] >= m.box.lo[k] + m.box.len[k];
      lo[k] = whole ? G.lo[k] : G.lo[k] + r;
      hi[k] = whole ? G.hi[k] : G.hi[k] - r;
      if (hi[k] < lo[k]) d.fail(key(g, "region_hi"), "the placement region is narrower than a grain diameter");
    }
    bool placed = false;
    std::fill(behind.begin(), behind.end(), 0);
    for (int attempt = 0; attempt < kAttempts && !placed; ++attempt) {
      double p[3];
      for (int k = 0; k < D; ++k) p[k] = rng.uniform(lo[k], hi[k]);
      if (grid.worst_overlap(p, r, xs, rs) > 0) continue;
      bool clear = true;
      for (size_t w = 0; w < m.walls.size() && clear; ++w)
        if (m.walls[w].gap(m.dim, p, r) < 0) {
          clear = false;
          ++behind[w];
        }
      if (!clear) continue;
      for (int k = 0; k < D; ++k) xs[D * i + k] = p[k];
      grid.insert(i, p);
      placed = true;
    }
    // Mostly behind a wall: the region reaches past the walls (a domain far larger than the
    // walled space, the region's own keys), whatever it holds.
    // (every wall that refused some: two walls facing each other each took under half of them)
    int walled = 0;
    std::string which;
    for (size_t w = 0; w < behind.size() && !placed; ++w)
      if (behind[w] > 0) {
        walled += behind[w];
        which += (which.empty() ? "" : ", ") + std::to_string(behind[w]) + " behind walls[" + std::to_string(w) + "]";
      }
    if (!placed && 2 * walled > kAttempts) {
      const std::string region = d.has(key(g, "region_lo")) ? key(g, "region_lo") : key(g, "count");
      d.fail(region, "could not place grain " + std::to_string(q + 1) + " of " + std::to_string(G.count) +
                         " at random: " + std::to_string(walled) + " of " + std::to_string(kAttempts) +
                         " random positions in its region (the domain unless region_lo and region_hi are given) "
                         "were behind walls (" +
                         which + "); give the group a region between the walls");
    }
    if (!placed) {
      double vol = 1, solid = 0;
      for (int k = 0; k < D; ++k) vol *= G.hi[k] - G.lo[k];
      for (int64_t j = first; j < first + G.count; ++j) solid += grain_volume(D, rs[j]);
      d.fail(key(g, "count"), "could not place grain " + std::to_string(q + 1) + " of " + std::to_string(G.count) +
                                  " at random without overlap (the group alone fills " + format_number(solid / vol) +
                                  " of its region; random addition jams near 0.55 in 2D and 0.38 in 3D): use a "
                                  "larger region, fewer grains, or placement = \"lattice\"");
    }
  }
}

void set_velocities(const SceneDesc& d, Model& m, int g, int64_t first, int64_t count, Rng& rng) {
  const int D = m.dim, R = m.rot;
  auto& v = m.init.v;
  const std::string kind = d.string(key(g, "velocity"));
  if (kind == "gaussian") {
    // Like LAMMPS `velocity create`: Gaussian components, zero total momentum, then scaled so
    // that the kinetic temperature 2 KE / (D (n - 1)) equals the requested value.
    const double T = d.real(key(g, "temperature"));
    double p[3] = {0, 0, 0}, mass = 0;
    for (int64_t i = first; i < first + count; ++i) {
      const double s = std::sqrt(T / m.init.mass[i]);
      for (int k = 0; k < D; ++k) {
        v[D * i + k] = s * rng.normal();
        p[k] += m.init.mass[i] * v[D * i + k];
      }
      mass += m.init.mass[i];
    }
    if (count > 1) {
      double ke = 0;
      for (int64_t i = first; i < first + count; ++i)
        for (int k = 0; k < D; ++k) {
          v[D * i + k] -= p[k] / mass;
          ke += 0.5 * m.init.mass[i] * v[D * i + k] * v[D * i + k];
        }
      const double target = 0.5 * D * (count - 1) * T;
      const double scale = ke > 0 ? std::sqrt(target / ke) : 0;
      for (int64_t i = first; i < first + count; ++i)
        for (int k = 0; k < D; ++k) v[D * i + k] *= scale;
    }
  } else if (kind == "explicit") {
    const auto vel = d.matrix(key(g, "velocities"));
    if (static_cast<int64_t>(vel.size()) != count)
      d.fail(key(g, "velocities"), "needs one velocity per grain (" + std::to_string(count) + ")");
    for (int64_t q = 0; q < count; ++q) {
      if (static_cast<int>(vel[q].size()) != D)
        d.fail(key(g, "velocities"), "every velocity needs " + std::to_string(D) + " components");
      for (int k = 0; k < D; ++k) v[D * (first + q) + k] = vel[q][k];
    }
  }
  if (d.has(key(g, "angular_velocities"))) {
    if (kind != "explicit") d.fail(key(g, "angular_velocities"), "angular_velocities need velocity = \"explicit\"");
    const auto w = d.matrix(key(g, "angular_velocities"));
    if (static_cast<int64_t>(w.size()) != count)
      d.fail(key(g, "angular_velocities"), "needs one angular velocity per grain");
    for (int64_t q = 0; q < count; ++q) {
      if (static_cast<int>(w[q].size()) != R)
        d.fail(key(g, "angular_velocities"), "every angular velocity needs " + std::to_string(R) + " component(s)");
      for (int k = 0; k < R; ++k) m.init.w[R * (first + q) + k] = w[q][k];
    }
  }
}

}  // namespace

// The grains of a checkpoint inside the group's region, frozen (grains[].frozen_from), in the
// order of their ids in the file.
void grains_from_checkpoint(const SceneDesc& d, Model& m, int g, Group& G) {
  const std::string k = key(g, "frozen_from");
  std::string path = d.string(k);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) && std::filesystem::path(path).is_relative() && !d.file.empty()) {
    const std::string beside = (std::filesystem::path(d.file).parent_path() / path).string();
    if (std::filesystem::exists(beside, ec)) path = beside;
  }
  if (d.has(key(g, "placement")))
    d.fail(key(g, "placement"), "a group taken from a checkpoint (frozen_from) is placed as it was");
  if (d.has(key(g, "frozen")) && !d.boolean(key(g, "frozen")))
    d.fail(key(g, "frozen"), "the grains of frozen_from are frozen");
  for (const char* leaf : {"count", "radius", "radius_min", "radius_max", "radii", "volume_fractions", "radius_list"})
    if (d.has(key(g, leaf)))
      d.fail(key(g, leaf), std::string(leaf) + " does not apply: the checkpoint gives the grains");
  try {
    const ckpt::RawCheckpoint c = ckpt::read_raw(path);
    if (c.system.dim != m.dim)
      d.fail(k, "'" + path + "' holds a " + std::to_string(c.system.dim) + "D system; this scene is " +
                    std::to_string(m.dim) + "D");
    const auto x = c.doubles("particle_x", path), r = c.doubles("particle_r", path);
    const auto id = c.ints("particle_id", path);
    const int64_t n = static_cast<int64_t>(r.size());
    if (static_cast<int64_t>(x.size()) != n * m.dim || static_cast<int64_t>(id.size()) != n)
      throw IoError("checkpoint '" + path + "' is corrupt: its grain arrays differ in length");
    std::vector<int64_t> order(n, -1);
    for (int64_t i = 0; i < n; ++i) {
      if (id[i] < 0 || id[i] >= n || order[id[i]] >= 0)
        throw IoError("checkpoint '" + path + "' is corrupt: bad grain ids");
      order[id[i]] = i;
    }
    m.checkpoints_read.push_back(path);
    G.placement = "checkpoint";
    G.frozen = true;
    for (int64_t q = 0; q < n; ++q) {
      const int64_t i = order[q];
      bool inside = true;
      for (int a = 0; a < m.dim; ++a) inside = inside && x[m.dim * i + a] >= G.lo[a] && x[m.dim * i + a] <= G.hi[a];
      if (!inside) continue;
      G.sites.insert(G.sites.end(), &x[m.dim * i], &x[m.dim * i] + m.dim);
      G.radius.push_back(r[i]);
    }
  } catch (const IoError& e) {
    d.fail(k, e.what());
  }
  G.count = static_cast<int64_t>(G.radius.size());
  if (G.count == 0) d.fail(k, "no grain of '" + path + "' lies in the group's region");
}

void check_explicit_positions(const SceneDesc& d, int dim) {
  for (int g = 0; g < d.group_count("grains"); ++g)
    if (d.string(key(g, "placement")) == "explicit") explicit_positions(d, g, dim);
}

std::string grain_size_key(const SceneDesc& d, int g) {
  const std::string prefix = "grains[" + std::to_string(g) + "].";
  for (const char* leaf : {"radius", "radius_min", "radius_max", "radii", "radius_list", "frozen_from"})
    if (d.has(prefix + leaf)) return prefix + leaf;
  return prefix + "radius";
}

std::string grain_mass_key(const SceneDesc& d, int g, int dim, double r) {
  const std::string density = "grains[" + std::to_string(g) + "].density";
  if (d.has(density) && std::abs(std::log(d.real(density))) > dim * std::abs(std::log(r))) return density;
  return grain_size_key(d, g);
}

void setup_grains(const SceneDesc& d, Model& m) {
  const int n_groups = d.group_count("grains");
  if (n_groups == 0) throw SceneError(FileLoc{d.file, 1, 1}, "the scene has no [[grains]] table");
  const int D = m.dim;
  const uint64_t seed = static_cast<uint64_t>(d.integer("scene.seed"));
  std::vector<Group> groups(n_groups);
  int64_t counted = 0;
  // Pass 1: counts and radii (random placement needs the largest radius of all groups).
  for (int g = 0; g < n_groups; ++g) {
    Group& G = groups[g];
    G.name = d.string(key(g, "name"));
    if (G.name.empty()) G.name = "group" + std::to_string(g);
    G.density = d.real(key(g, "density"));
    region_of(d, m, g, G);
    if (d.has(key(g, "frozen_from"))) {
      grains_from_checkpoint(d, m, g, G);
      continue;
    }
    G.placement = d.string(key(g, "placement"));
    G.frozen = d.boolean(key(g, "frozen"));
    G.count = group_count(d, m, g, G);
    // Before anything is allocated for them (their radii are not known yet: the footprint of
    // grains of one size), with the groups before.
    counted += G.count;
    check_memory(d, m, counted, key(g, d.has(key(g, "count")) ? "count" : "placement"));
    Rng rng(seed, 2 * g);
    G.radius = draw_radii(d, m, g, G.count, rng);
  }
  int64_t n = 0;
  for (const Group& G : groups) n += G.count;
  m.n_grains = n;
  auto& I = m.init;
  I.x.assign(n * D, 0);
  I.v.assign(n * D, 0);
  I.w.assign(n * m.rot, 0);
  I.radius.clear();
  I.mass.clear();
  I.inertia.clear();
  I.frozen.clear();
  I.group.clear();
  for (int g = 0; g < n_groups; ++g) {
    const Group& G = groups[g];
    // A radius or a density at the ends of the doubles' range makes a mass of 0 or infinity.
    for (double r : G.radius) {
      const double mass = G.density * grain_volume(D, r), inertia = mass * r * r;
      if (!(mass > 0) || !std::isfinite(mass) || !(inertia > 0) || !std::isfinite(inertia))
        d.fail(grain_mass_key(d, g, D, r), "a grain of radius " + format_number(r) + " and density " +
                                               format_number(G.density) + " has a mass of " + format_number(mass) +
                                               " kg and a moment of inertia of " + format_number(inertia) +
                                               ": both must be finite and positive");
      I.radius.push_back(r);
      I.mass.push_back(mass);
      I.inertia.push_back(inertia_factor(D) * mass * r * r);
      I.frozen.push_back(G.frozen ? 1 : 0);
      I.group.push_back(g);
    }
    m.group_names.push_back(G.name);
  }
  m.r_max = *std::max_element(I.radius.begin(), I.radius.end());
  m.r_min = *std::min_element(I.radius.begin(), I.radius.end());
  m.r_mean = std::accumulate(I.radius.begin(), I.radius.end(), 0.0) / n;
  m.a_max = 2 * m.r_max;
  // Pass 2: positions (lattice/explicit first so that random grains avoid them), velocities.
  PlacementGrid grid(m, 2 * m.r_max);
  std::vector<int64_t> first(n_groups);
  for (int g = 0, f = 0; g < n_groups; f += groups[g].count, ++g) first[g] = f;
  for (int g = 0; g < n_groups; ++g) {
    const Group& G = groups[g];
    if (G.placement == "random") continue;
    for (int64_t q = 0; q < G.count; ++q) {
      double* x = &I.x[D * (first[g] + q)];
      for (int k = 0; k < D; ++k) {
        x[k] = G.sites[D * q + k];
        const double lo = m.box.lo[k], hi = m.box.lo[k] + m.box.len[k];
        if (m.box.periodic[k]) {
          x[k] = lo + (x[k] - lo) - m.box.len[k] * std::floor((x[k] - lo) / m.box.len[k]);
        } else if (x[k] < lo || x[k] > hi) {
          d.fail(key(g, G.placement == "lattice" ? "region_hi"
                                                 : (G.placement == "checkpoint" ? "frozen_from" : "positions")),
                 "grain " + std::to_string(q) + " of grains[" + std::to_string(g) + "] lies outside the domain");
        }
      }
      grid.insert(first[g] + q, x);
    }
  }
  for (int g = 0; g < n_groups; ++g) {
    if (groups[g].placement != "random") continue;
    Rng rng(seed, 2 * g + 1);
    place_random(d, m, g, groups[g], first[g], rng, grid);
  }
  for (int g = 0; g < n_groups; ++g) {
    Rng rng(seed, 1000 + g);
    set_velocities(d, m, g, first[g], groups[g].count, rng);
    // Keys that only some choices read: reading them here keeps check_all_used() honest.
    if (groups[g].placement != "lattice")
      for (const char* k : {"lattice", "spacing", "lattice_origin"})
        if (d.has(key(g, k))) d.fail(key(g, k), std::string(k) + " is only read with placement = \"lattice\"");
  }
  m.n_frozen = std::count(I.frozen.begin(), I.frozen.end(), 1);
  double msum = 0;
  int64_t nfree = 0;
  m.m_min = 1e308;
  for (int64_t i = 0; i < n; ++i)
    if (!I.frozen[i]) {
      msum += I.mass[i];
      ++nfree;
      m.m_min = std::min(m.m_min, I.mass[i]);
    }
  m.m_mean = nfree ? msum / nfree : I.mass[0];
  if (nfree == 0) m.m_min = *std::min_element(I.mass.begin(), I.mass.end());
}

// The key that best locates grain group g in the file: its explicit positions if given, else its
// first key (the line of its [[grains]] table).
static std::string group_location_key(const SceneDesc& d, int g) {
  const std::string prefix = "grains[" + std::to_string(g) + "].";
  if (d.has(prefix + "positions")) return prefix + "positions";
  std::string best;
  FileLoc best_loc{};
  for (const auto& [path, e] : d.entries)
    if (path.rfind(prefix, 0) == 0 && (best.empty() || e.loc.line < best_loc.line)) {
      best = path;
      best_loc = e.loc;
    }
  return best;
}

void check_initial_overlaps(const Model& m) {
  const int D = m.dim;
  const auto& I = m.init;
  PlacementGrid grid(m, 2 * m.r_max);
  for (int64_t i = 0; i < m.n_grains; ++i) {
    const double* x = &I.x[D * i];
    int64_t j = -1;
    const double f = grid.worst_overlap(x, I.radius[i], I.x, I.radius, &j);
    if (f > m.limits.max_overlap && !(I.frozen[i] && I.frozen[j]))
      m.desc.fail(group_location_key(m.desc, I.group[i]),
                  "grains " + std::to_string(j) + " and " + std::to_string(i) + " overlap by " +
                      format_number(100 * f) + "% of the smaller radius at t = 0, beyond limits.max_overlap = " +
                      format_number(m.limits.max_overlap) + ": move them apart or reduce their radii");
    grid.insert(i, x);
    for (size_t w = 0; w < m.walls.size(); ++w) {
      const double gap = m.walls[w].gap(D, x, I.radius[i]);
      if (!I.frozen[i] && -gap > m.limits.max_overlap * I.radius[i])
        m.desc.fail("walls[" + std::to_string(w) + "].point",
                    "grain " + std::to_string(i) + " overlaps wall " + std::to_string(w) + " by " +
                        format_number(-100 * gap / I.radius[i]) + "% of its radius at t = 0");
    }
  }
}

}  // namespace silt::dem
