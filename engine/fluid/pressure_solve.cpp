#include "fluid/pressure_solve.hpp"

#include "fluid/multigrid.hpp"
#include "fluid/operators.hpp"

namespace silt::fluid {
namespace {

AxisKind cell_kind(bool dirichlet_lo, bool dirichlet_hi) {
  if (dirichlet_lo) return dirichlet_hi ? AxisKind::kCellDD : AxisKind::kCellDN;
  return dirichlet_hi ? AxisKind::kCellND : AxisKind::kCellNN;
}

// The velocity's condition on a face, for a tangential component: a given value (no-slip,
// inflow) is Dirichlet, the others (free slip, outflow) Neumann.
bool tangential_dirichlet(BcType t) { return t == BcType::kNoSlip || t == BcType::kInflow; }

}  // namespace

std::array<SolverAxis, 3> pressure_axes(const Grid& g) {
  std::array<SolverAxis, 3> ax{};
  for (int b = 0; b < g.dim; ++b) {
    ax[b].m = g.n[b];
    ax[b].h = g.h[b];
    ax[b].kind = g.periodic(b)
                     ? AxisKind::kPeriodic
                     : cell_kind(g.pbc(b, 0) == PressureBc::kDirichlet, g.pbc(b, 1) == PressureBc::kDirichlet);
  }
  return ax;
}

std::array<SolverAxis, 3> velocity_axes(const Grid& g, int a) {
  std::array<SolverAxis, 3> ax{};
  const auto d = unknown_dims(g, a);
  for (int b = 0; b < g.dim; ++b) {
    ax[b].m = d[b];
    ax[b].h = g.h[b];
    if (g.periodic(b)) ax[b].kind = AxisKind::kPeriodic;
    else if (b == a) ax[b].kind = g.bc[b][1].type == BcType::kOutflow ? AxisKind::kFaceDN : AxisKind::kFaceDD;
    else ax[b].kind = cell_kind(tangential_dirichlet(g.bc[b][0].type), tangential_dirichlet(g.bc[b][1].type));
  }
  return ax;
}

void make_pressure_solver(const FluidParams& p, FluidWorkspace& w) {
  if (p.projection == Projection::kFft) {
    w.poisson = std::make_unique<FastSolver>(p.grid.dim, pressure_axes(p.grid));
    w.multigrid.reset();
    return;
  }
  w.poisson.reset();
  PoissonSolverOptions opt;
  opt.cg.tolerance = p.tolerance;
  opt.cg.max_iterations = p.max_iterations;
  w.multigrid = std::make_shared<PoissonSolver>(p.grid, 0.0, opt);
}

std::unique_ptr<FastSolver> make_helmholtz_solver(const Grid& g, int a) {
  return std::make_unique<FastSolver>(g.dim, velocity_axes(g, a));
}

linalg::SolveReport solve_pressure(const FluidParams& p, FluidWorkspace& w) {
  const Grid& g = p.grid;
  linalg::SolveReport r;
  if (w.poisson) {
    // (phi written by the solve's last pass)
    const SolveRows phi = unknown_rows(g, w.L, -1, w.phi.data());
    w.poisson->solve(w.cells.data(), 0.0, {nullptr, 1.0, &phi});
    return r;
  }
  PoissonSolver& mg = *w.multigrid;
  const auto n = static_cast<Eigen::Index>(g.cells());
  // (-Lap) phi = -div u* / (alpha dt), from phi = 0 (the increment).
  linalg::SolveOptions opt;
  opt.tolerance = p.tolerance;
  opt.max_iterations = p.max_iterations;
  mg.set_cg_options(opt);
  w.mg_x.setZero(n);
  r = mg.solve(Eigen::Map<const linalg::Vector>(w.cells.data(), n), w.mg_x);
  scatter_unknowns(g, w.L, -1, w.mg_x.data(), w.phi.data());
  return r;
}

size_t pressure_solver_bytes(const FluidWorkspace& w) {
  size_t b = 0;
  if (w.poisson) b += w.poisson->bytes();
  for (const auto& h : w.helmholtz)
    if (h) b += h->bytes();
  return b;
}

}  // namespace silt::fluid
