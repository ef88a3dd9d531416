// Measurements of a fluid state: energy, enstrophy, divergence, the fields at the cell centres
// (frames, VTK) and values at points (line probes). They read the State's arrays through a
// padded copy whose ghosts hold the boundary conditions, so that wall values are exact.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>

#include "core/large_array.hpp"
#include "core/parallel.hpp"
#include "fluid/boundaries.hpp"
#include "fluid/module.hpp"
#include "fluid/operators.hpp"
#include "fluid/stencil_kernels.hpp"
#include "fluid/step.hpp"
#include "fluid/sweep_for.hpp"

namespace silt::fluid {
namespace {

// The arrays of a padded copy, and the grid they were filled for: its dimension, cells and
// boundary types, which decide the places a copy writes.
struct PaddedArrays {
  std::vector<int64_t> grid;
  std::array<LargeArray<double>, 3> u;
  LargeArray<double> p;
};

std::vector<int64_t> grid_key(const Grid& g) {
  std::vector<int64_t> k = {g.dim, g.n[0], g.n[1], g.n[2]};
  for (const auto& axis : g.bc)
    for (const Bc& bc : axis) k.push_back(static_cast<int64_t>(bc.type));
  return k;
}

// One set of arrays kept from one measurement to the next. In fresh memory a copy cost more than
// the measurement: the kernel clears every page it hands out (a 128^3 vortex sampling
// fluid.enstrophy at every step spent 37 % of its run in page faults and their clearing, a
// sample 0.75 of a step). The set is reused only for the grid it was filled for, whose copies
// write the same places: the places none writes keep the zeros of the first, as fresh memory
// would, and the values measured are the same. Another grid's takes it and frees it.
class PaddedCache {
 public:
  PaddedArrays take(const Grid& g) {
    std::lock_guard<std::mutex> lock(mutex_);
    PaddedArrays a;
    std::vector<int64_t> key = grid_key(g);
    if (kept_ && kept_->grid == key) a = std::move(*kept_);
    kept_.reset();
    a.grid = std::move(key);
    return a;
  }
  void give(PaddedArrays&& a) {
    std::lock_guard<std::mutex> lock(mutex_);
    kept_ = std::move(a);
  }

 private:
  std::mutex mutex_;
  std::optional<PaddedArrays> kept_;
};

PaddedCache& padded_cache() {
  static PaddedCache cache;
  return cache;
}

struct PaddedState {
  Layout L;
  PaddedArrays a;
  PaddedState() = default;
  PaddedState(const PaddedState&) = delete;
  PaddedState& operator=(const PaddedState&) = delete;
  PaddedState(PaddedState&&) = default;
  PaddedState& operator=(PaddedState&&) = default;
  ~PaddedState() {
    if (!a.grid.empty()) padded_cache().give(std::move(a));
  }
  Padded ptr() { return {a.u[0].data(), a.u[1].data(), a.u[2].data()}; }
  PaddedConst cptr() const { return {a.u[0].data(), a.u[1].data(), a.u[2].data()}; }
};

// Rows copied in parallel. Without the pressure (p empty) where only the velocity is read.
PaddedState padded(const FluidParams& fp, const State& s, bool with_pressure = true) {
  const Grid& g = fp.grid;
  PaddedState ps;
  ps.L = Layout(g);
  ps.a = padded_cache().take(g);
  const FluidFields f = fluid_fields();
  const auto copy_rows = [&](const std::vector<double>& src, LargeArray<double>& to, const std::array<int64_t, 3>& d) {
    to.resize(static_cast<size_t>(ps.L.size));
    sweep_for(g.cells(), d[1] * d[2], 16, [&](int64_t b, int64_t e) {
      for (int64_t row = b; row < e; ++row)
        std::copy_n(src.data() + d[0] * row, d[0], to.data() + ps.L.at(0, row % d[1], row / d[1]));
    });
  };
  for (int a = 0; a < g.dim; ++a) copy_rows(s.module_field(f.u[a]), ps.a.u[a], g.face_dims(a));
  fill_velocity_ghosts(g, ps.L, ps.ptr());
  if (!with_pressure) return ps;
  copy_rows(s.module_field(f.p), ps.a.p, g.n);
  fill_pressure_ghosts(g, ps.L, ps.a.p.data());
  return ps;
}

// Weight of face index i along its own axis: 1 inside, 1/2 on a wall (non-periodic), 0 for
// the periodic copy n.
double face_weight(const Grid& g, int a, int64_t i) {
  if (g.periodic(a)) return i < g.n[a] ? 1.0 : 0.0;
  return (i == 0 || i == g.n[a]) ? 0.5 : 1.0;
}

// f(row, i, padded index) for every cell of the rows of cells [b, e) (row = j + n_y k).
template <class F>
void for_each_cell_row(const Grid& g, const Layout& L, int64_t b, int64_t e, F&& f) {
  for (int64_t row = b; row < e; ++row) {
    const int64_t q0 = L.at(0, row % g.n[1], row / g.n[1]);
    for (int64_t i = 0; i < g.n[0]; ++i) f(row, i, q0 + i);
  }
}

template <int D>
void cell_vorticity(const Grid& g, const PaddedState& ps, std::vector<double>& out) {
  const int nc = D == 3 ? 3 : 1;
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const PaddedConst c = ps.cptr();
  out.resize(static_cast<size_t>(g.cells() * nc));
  sweep_for(g.cells(), g.n[1] * g.n[2], 16, [&](int64_t b, int64_t e) {
    for_each_cell_row(g, ps.L, b, e, [&](int64_t row, int64_t i, int64_t q) {
      cell_vorticity_kernel<D>(c.data(), q, ps.L.s.data(), inv_h, &out[nc * (row * g.n[0] + i)]);
    });
  });
}

// (1/2) sum over cells of |omega|^2 times the cell volume, in rows of cells summed in fixed
// chunks (the same sum on any number of threads), without storing the vorticity.
template <int D>
double enstrophy_of(const Grid& g, const PaddedState& ps) {
  const int nc = D == 3 ? 3 : 1;
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const PaddedConst c = ps.cptr();
  const double sum = deterministic_sum(g.n[1] * g.n[2], 16, [&](int64_t b, int64_t e) {
    double acc = 0, w[3];
    for_each_cell_row(g, ps.L, b, e, [&](int64_t, int64_t, int64_t q) {
      cell_vorticity_kernel<D>(c.data(), q, ps.L.s.data(), inv_h, w);
      for (int k = 0; k < nc; ++k) acc += w[k] * w[k];
    });
    return acc;
  });
  return 0.5 * sum * g.cell_volume();
}

GridField grid_field(const Grid& g, const std::string& name, const std::string& unit, int components) {
  GridField f;
  f.name = name;
  f.unit = unit;
  f.components = components;
  f.nx = static_cast<int>(g.n[0]);
  f.ny = static_cast<int>(g.n[1]);
  f.nz = g.dim == 3 ? static_cast<int>(g.n[2]) : 1;
  f.lo = g.lo;
  f.h = g.h;
  if (g.dim == 2) f.h[2] = g.h[0];
  return f;
}

GridField vorticity_field(const Grid& g, const PaddedState& ps) {
  GridField vort = grid_field(g, "vorticity", "1/s", g.dim == 3 ? 3 : 1);
  if (g.dim == 2) cell_vorticity<2>(g, ps, vort.value);
  else cell_vorticity<3>(g, ps, vort.value);
  return vort;
}

// Linear interpolation at x of values on a lattice whose point (i, j, k) sits at lo + (i + off) h
// and whose value there is value(padded index of (i, j, k)). Points outside the box are taken at
// its nearest boundary point, so the lattice indices read run from -1 (a ghost, for off 1/2) to n.
template <class Value>
double interpolate(const Grid& g, const Layout& L, Value&& value, const std::array<double, 3>& off,
                   const std::array<double, 3>& x) {
  std::array<int64_t, 3> i0{0, 0, 0};
  std::array<double, 3> t{0, 0, 0};
  for (int b = 0; b < g.dim; ++b) {
    const double r = std::clamp((x[b] - g.lo[b]) / g.h[b] - off[b], -off[b], static_cast<double>(g.n[b]) - off[b]);
    i0[b] = static_cast<int64_t>(std::floor(r));
    t[b] = r - static_cast<double>(i0[b]);
  }
  double sum = 0;
  const int corners = 1 << g.dim;
  for (int c = 0; c < corners; ++c) {
    double w = 1;
    std::array<int64_t, 3> idx = i0;
    for (int b = 0; b < g.dim; ++b) {
      const int up = (c >> b) & 1;
      idx[b] += up;
      w *= up ? t[b] : 1 - t[b];
    }
    if (w != 0) sum += w * value(L.at(idx[0], idx[1], idx[2]));
  }
  return sum;
}

// The sum over the faces of component a of face_weight (by the face's index along a) times f of
// its value, in fixed blocks of rows (the same bits on any number of threads).
template <class F>
double weighted_face_sum(const Grid& g, int a, const std::vector<double>& u, F&& f) {
  const auto d = g.face_dims(a);
  const auto sums = deterministic_sums<1>(d[1] * d[2], 64, [&](int64_t b, int64_t end) {
    double acc = 0;
    for (int64_t row = b; row < end; ++row) {
      const double* v = u.data() + row * d[0];
      if (a == 0) {
        for (int64_t i = 0; i < d[0]; ++i) acc += face_weight(g, 0, i) * f(v[i]);
        continue;
      }
      // rows are (j, k) with j fastest: the index along y is row % d[1], along z row / d[1]
      const double w = face_weight(g, a, a == 1 ? row % d[1] : row / d[1]);
      if (w == 0) continue;
      for (int64_t i = 0; i < d[0]; ++i) acc += w * f(v[i]);
    }
    return std::array<double, 1>{acc};
  });
  return sums[0];
}

}  // namespace

double kinetic_energy(const FluidParams& p, const State& s) {
  const Grid& g = p.grid;
  const FluidFields f = fluid_fields();
  double e = 0;
  for (int a = 0; a < g.dim; ++a) e += weighted_face_sum(g, a, s.module_field(f.u[a]), [](double v) { return v * v; });
  return 0.5 * p.density * e * g.cell_volume();
}

double mean_velocity(const FluidParams& p, const State& s, int a) {
  const double sum = weighted_face_sum(p.grid, a, s.module_field(fluid_fields().u[a]), [](double v) { return v; });
  return sum / static_cast<double>(p.grid.cells());
}

double enstrophy(const FluidParams& p, const State& s) {
  const PaddedState ps = padded(p, s, false);
  return p.grid.dim == 2 ? enstrophy_of<2>(p.grid, ps) : enstrophy_of<3>(p.grid, ps);
}

double max_divergence(const FluidParams& p, const State& s) {
  const Grid& g = p.grid;
  const PaddedState ps = padded(p, s, false);
  std::vector<double> cells(static_cast<size_t>(g.cells()));
  return divergence_max(g, ps.L, ps.cptr(), cells.data());
}

std::vector<GridField> cell_fields(const FluidParams& p, const State& s, std::string_view only) {
  const Grid& g = p.grid;
  const PaddedState ps = padded(p, s);
  std::vector<GridField> out;
  const auto wanted = [&](std::string_view name) { return only.empty() || only == name; };
  // A field filled cell by cell: at(its values at the cell, the cell's padded index).
  const auto cells = [&](GridField f, auto&& at) {
    f.value.assign(static_cast<size_t>(g.cells() * f.components), 0.0);
    for (int64_t k = 0; k < g.n[2]; ++k)
      for (int64_t j = 0; j < g.n[1]; ++j)
        for (int64_t i = 0; i < g.n[0]; ++i) at(&f.value[f.components * g.cell(i, j, k)], ps.L.at(i, j, k));
    out.push_back(std::move(f));
  };
  if (wanted("velocity"))
    cells(grid_field(g, "velocity", "m/s", 3), [&](double* v, int64_t q) {
      for (int a = 0; a < g.dim; ++a) v[a] = 0.5 * (ps.a.u[a][q] + ps.a.u[a][q + ps.L.s[a]]);
    });
  if (wanted("pressure")) cells(grid_field(g, "pressure", "Pa", 1), [&](double* v, int64_t q) { *v = ps.a.p[q]; });
  if (wanted("vorticity")) out.push_back(vorticity_field(g, ps));
  return out;
}

namespace {

// A field at x from a padded state. The velocity components and the pressure are interpolated
// from their faces and cell centres; the vorticity from its natural places, the edges of the
// cells (in 2D the corners), where omega_z = dv/dx - du/dy is the centred difference of the face
// velocities (exact for a quadratic profile, the wall's ghost included): second order, where the
// cell-centred value of the cell holding x was first order, h/2 off on a channel's centreline.
// In 3D the vorticity's modulus, of its three interpolated components.
double sample_in(const Grid& g, const PaddedState& ps, const std::string& field, const std::array<double, 3>& x) {
  std::array<double, 3> off{0.5, 0.5, 0.5};
  const auto at = [](const LargeArray<double>& v) { return [&v](int64_t q) { return v[q]; }; };
  if (field == "u" || field == "v" || field == "w") {
    const int a = field[0] == 'u' ? 0 : (field[0] == 'v' ? 1 : 2);
    off[a] = 0;
    return interpolate(g, ps.L, at(ps.a.u[a]), off, x);
  }
  if (field == "p") return interpolate(g, ps.L, at(ps.a.p), off, x);
  const double inv_h[3] = {1 / g.h[0], 1 / g.h[1], 1 / g.h[2]};
  const PaddedConst c = ps.cptr();
  const int64_t* s = ps.L.s.data();
  // The component about axis e (a, b the two others, cyclic) at its edges: off 0 along a and b.
  const auto component = [&]<int A, int B>(std::integral_constant<int, A>, std::integral_constant<int, B>) {
    std::array<double, 3> edge{0.5, 0.5, 0.5};
    edge[A] = edge[B] = 0;
    return interpolate(
        g, ps.L, [&](int64_t q) { return vorticity_kernel<A, B>(c.data(), q, s, inv_h); }, edge, x);
  };
  using I0 = std::integral_constant<int, 0>;
  using I1 = std::integral_constant<int, 1>;
  using I2 = std::integral_constant<int, 2>;
  const double wz = component(I0{}, I1{});
  if (g.dim == 2) return wz;
  const double wx = component(I1{}, I2{}), wy = component(I2{}, I0{});
  return std::sqrt(wx * wx + wy * wy + wz * wz);
}

}  // namespace

double sample(const FluidParams& p, const State& s, const std::string& field, const std::array<double, 3>& x) {
  return sample_in(p.grid, padded(p, s), field, x);
}

std::vector<LineSample> line_samples(const Model& m, const State& s) {
  const FluidParams& p = m.params.get<FluidParams>();
  std::vector<LineSample> out;
  if (p.lines.empty()) return out;
  const PaddedState ps = padded(p, s);
  for (const LineProbe& l : p.lines) {
    LineSample ls;
    ls.name = l.name;
    ls.field = l.field;
    for (int k = 0; k < l.points; ++k) {
      const double t = static_cast<double>(k) / (l.points - 1);
      std::array<double, 3> x{0, 0, 0};
      for (int a = 0; a < m.dim; ++a) x[a] = l.from[a] + t * (l.to[a] - l.from[a]);
      ls.s.push_back(t);
      ls.x.push_back(x);
      ls.value.push_back(sample_in(p.grid, ps, l.field, x));
    }
    out.push_back(std::move(ls));
  }
  return out;
}

}  // namespace silt::fluid
