// The linear-algebra layer on a synthetic 3D resistance matrix: N spheres of radius 1 on a
// jittered simple cubic lattice at solid fraction 0.45, every pair with a gap below h_max = 0.5
// connected by lubrication (normal xi_N = 1/h, tangential xi_T = log(1/h), both constant below
// the cutoff h_min; Peyneau 2009 eq. 1.28-1.29 in form), unknowns the velocity and angular
// velocity of every sphere (6 N), and a Stokes drag of 1e-3 on each (the singular rigid modes
// removed). One sphere in three is moved to a gap of 1e-9 to 1e-2 (log-uniform) above its
// neighbour, so the cutoff h_min (1e-2 to 1e-8) sets the conditioning. The matrix of the next
// step has every gap changed by up to 5 % (the adaptive step of Peyneau's sec. 2.2.4 bounds the
// change of Xi's entries so): what a stepper meets. Cost of each method against the others: the
// factorisation, the direct solve, one solve with the factor (CHOLMOD's triangular solves and
// silt's, on one thread and on two), one product with the matrix, CG preconditioned by the
// previous step's factor, Jacobi CG and plain CG, all to a relative residual of 1e-8 (at most
// 20,000 iterations). One thread, but for the rows of silt's solve on two. Its solve and PCG again
// with the factor's values rounded to floats (the preconditioner's single precision).
//
// Usage: linalg_solvers [N...]    (default: 1000 4000)        Writes bench/results/linalg.csv.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "silt/linalg.hpp"

using namespace silt::linalg;

namespace {

struct Sphere {
  double x[3];
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<Sphere> lattice(int n, double phi, unsigned seed, double& box) {
  const int side = static_cast<int>(std::ceil(std::cbrt(n)));
  const double volume = n * 4.0 / 3.0 * M_PI / phi;
  box = std::cbrt(volume);
  const double s = box / side;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const double jitter = std::max(0.0, (s - 2.0) / 2 - 1e-3);  // never overlapping
  std::vector<Sphere> out;
  for (int i = 0; i < side && static_cast<int>(out.size()) < n; ++i)
    for (int j = 0; j < side && static_cast<int>(out.size()) < n; ++j)
      for (int k = 0; k < side && static_cast<int>(out.size()) < n; ++k)
        out.push_back(
            {{(i + 0.5) * s + jitter * u(rng), (j + 0.5) * s + jitter * u(rng), (k + 0.5) * s + jitter * u(rng)}});
  // One sphere in three brought to a gap of 1e-9 to 1e-2 (log-uniform) above its neighbour in z
  // (the next one in the same column), as grains near contact in a dense paste.
  std::uniform_real_distribution<double> decade(-9, -2);
  for (size_t a = 0; a + 1 < out.size(); a += 3) {
    if ((a + 1) % side == 0) continue;  // the top of a column
    const double gap = std::pow(10.0, decade(rng));
    out[a + 1].x[0] = out[a].x[0];
    out[a + 1].x[1] = out[a].x[1];
    out[a + 1].x[2] = out[a].x[2] + 2 + gap;
  }
  return out;
}

// The resistance matrix Xi = sum over pairs of G^T D G + drag (periodic box).
// `change`: every gap multiplied by 1 + change * U(-1, 1), the next step's matrix.
SparseMatrix resistance(const std::vector<Sphere>& p, double box, double h_max, double h_min, double change = 0) {
  const int n = static_cast<int>(p.size());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Triplet<double>> t;
  auto add_block = [&](int row, int col, const Eigen::Matrix<double, 6, 6>& m) {
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b)
        if (m(a, b) != 0) t.emplace_back(6 * row + a, 6 * col + b, m(a, b));
  };
  auto cross_matrix = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d c;
    c << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return c;
  };
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, 6, 6> drag = Eigen::Matrix<double, 6, 6>::Identity() * 1e-3;
    add_block(i, i, drag);
    for (int j = i + 1; j < n; ++j) {
      Eigen::Vector3d d;
      for (int k = 0; k < 3; ++k) {
        d[k] = p[j].x[k] - p[i].x[k];
        d[k] -= box * std::round(d[k] / box);
      }
      const double dist = d.norm();
      double h = dist - 2.0;
      if (h > h_max) continue;
      if (change > 0) h *= 1 + change * u(rng);
      const Eigen::Vector3d nrm = d / dist;
      const double hc = std::max(h, h_min);
      const double xn = 1.0 / hc, xt = std::log(1.0 / hc);
      const Eigen::Matrix3d nn = nrm * nrm.transpose();
      const Eigen::Matrix3d dm = xn * nn + xt * (Eigen::Matrix3d::Identity() - nn);
      // u = V_j - V_i - w_j x n - w_i x n  (radius 1): G = [-I, -[n]x^T..]: with w x n = -[n]x w.
      Eigen::Matrix<double, 3, 12> g;
      const Eigen::Matrix3d nx = cross_matrix(nrm);
      g << -Eigen::Matrix3d::Identity(), nx, Eigen::Matrix3d::Identity(), nx;
      const Eigen::Matrix<double, 12, 12> blk = g.transpose() * dm * g;
      add_block(i, i, blk.block<6, 6>(0, 0));
      add_block(i, j, blk.block<6, 6>(0, 6));
      add_block(j, i, blk.block<6, 6>(6, 0));
      add_block(j, j, blk.block<6, 6>(6, 6));
    }
  }
  SparseMatrix a(6 * n, 6 * n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::vector<int> sizes;
  for (int k = 1; k < argc; ++k) sizes.push_back(std::stoi(argv[k]));
  if (sizes.empty()) sizes = {1000, 4000};
  const std::string csv = std::string(SILT_SOURCE_DIR) + "/bench/results/linalg.csv";
  std::ofstream out(csv);
  out << "n_spheres,h_min,unknowns,nonzeros,method,setup_s,solve_s,iterations,residual,factor_mib\n";
  std::printf("%6s %7s %8s %10s  %-54s %9s %9s %6s %9s %10s\n", "N", "h_min", "unknowns", "nonzeros", "method",
              "setup s", "solve s", "iters", "residual", "factor MiB");
  // One thread throughout, but for the row of silt's solve on two.
  tbb::task_arena one(1);
  int status = 0;
  one.execute([&] {
    for (int n : sizes)
      for (double h_min : {1e-2, 1e-4, 1e-6, 1e-8}) {
        double box = 0;
        std::vector<Sphere> p = lattice(n, 0.45, 1, box);
        const SparseMatrix a0 = resistance(p, box, 0.5, h_min);
        const SparseMatrix a1 = resistance(p, box, 0.5, h_min, 0.05);
        std::mt19937_64 rng(2);
        Vector b(a1.rows());
        std::normal_distribution<double> g;
        for (int64_t i = 0; i < b.size(); ++i) b[i] = g(rng);
        const SolveOptions opt{1e-8, 20000};
        auto row = [&](const char* method, double setup, double solve, int iters, double residual, double mib) {
          std::printf("%6d %7.0e %8lld %10lld  %-54s %9.4f %9.6f %6d %9.2e %10.1f\n", n, h_min,
                      static_cast<long long>(a1.rows()), static_cast<long long>(a1.nonZeros()), method, setup, solve,
                      iters, residual, mib);
          std::string name = method;  // no comma inside a CSV field
          std::replace(name.begin(), name.end(), ',', ';');
          out << n << "," << h_min << "," << a1.rows() << "," << a1.nonZeros() << "," << name << "," << setup << ","
              << solve << "," << iters << "," << residual << "," << mib << "\n";
        };
        // The previous step's factor.
        CholeskyFactor old;
        auto t0 = std::chrono::steady_clock::now();
        old.analyze(a0);
        const double analyze_s = seconds_since(t0);
        t0 = std::chrono::steady_clock::now();
        if (!old.factorize(a0).ok()) {
          status = 1;
          return;
        }
        const double factor_s = seconds_since(t0);
        const double mib = old.factor_bytes() / 1048576.0;
        // Direct: factorise this step's matrix (analysis reused when the pattern holds) and solve.
        {
          CholeskyFactor f;
          t0 = std::chrono::steady_clock::now();
          f.analyze(a1);
          if (!f.factorize(a1).ok()) {
            status = 1;
            return;
          }
          const double setup = seconds_since(t0);
          Vector x;
          t0 = std::chrono::steady_clock::now();
          f.solve(b, x);
          const double solve = seconds_since(t0);
          const double res = (b - a1 * x).norm() / b.norm();
          row("direct (analyse+factor)", setup, solve, 0, res, f.factor_bytes() / 1048576.0);
          row("  of which analyse", analyze_s, 0, 0, 0, 0);
          row("  refactor (same pattern)", factor_s, 0, 0, 0, mib);
        }
        {
          // One solve with the factor (PCG's main cost per iteration): CHOLMOD's triangular solves,
          // then silt's on 1 and 2 threads (the same bits on both), best of 10 after one untimed.
          auto best_solve = [&](int threads) {
            tbb::task_arena arena(threads);
            double best = 1e30;
            arena.execute([&] {
              Vector x;
              for (int r = 0; r < 11; ++r) {
                const auto s0 = std::chrono::steady_clock::now();
                old.apply(b, x);  // solve(), or in single precision when set
                if (r > 0) best = std::min(best, seconds_since(s0));
              }
            });
            return best;
          };
          old.use_cholmod_solve(true);
          row("factor solve; CHOLMOD", 0, best_solve(1), 0, 0, mib);
          old.use_cholmod_solve(false);
          const SolveSplit sp = old.solve_split();
          char how[96];
          std::snprintf(how, sizeof how, "factor solve; silt 1 thread (%lld tasks %.0f%%; shared %.0f%%)",
                        static_cast<long long>(sp.tasks), 100 * sp.in_tasks, 100 * sp.shared);
          row(how, 0, best_solve(1), 0, 0, mib);
          row("factor solve; silt 2 threads", 0, best_solve(2), 0, 0, mib);
          // The factor's values rounded to floats (a preconditioner's solve): half the bytes.
          old.set_single_preconditioner(true);
          if (old.applies_single()) {
            row("factor solve; silt single precision, 1 thread", 0, best_solve(1), 0, 0, mib / 2);
            row("factor solve; silt single precision, 2 threads", 0, best_solve(2), 0, 0, mib / 2);
          }
        }
        const SparseOperator op(a1);
        {
          // One product with the matrix (CG's other cost per iteration): best of 50.
          Vector x = Vector::Ones(b.size()), y;
          double best = 1e30;
          for (int r = 0; r < 51; ++r) {
            t0 = std::chrono::steady_clock::now();
            op.apply(x, y);
            if (r > 0) best = std::min(best, seconds_since(t0));
          }
          row("product with the matrix", 0, best, 0, 0, 0);
        }
        {
          Vector x = Vector::Zero(b.size());
          t0 = std::chrono::steady_clock::now();
          const SolveReport r = conjugate_gradient(op, b, x, opt, &old);
          const bool single = old.applies_single();
          row(single ? "PCG, previous factor (single precision)" : "PCG, previous factor (single refused: double)", 0,
              seconds_since(t0), r.iterations, r.residual, single ? mib / 2 : mib);
        }
        {
          old.set_single_preconditioner(false);
          Vector x = Vector::Zero(b.size());
          t0 = std::chrono::steady_clock::now();
          const SolveReport r = conjugate_gradient(op, b, x, opt, &old);
          row("PCG, previous factor (double precision)", 0, seconds_since(t0), r.iterations, r.residual, mib);
        }
        {
          Vector x = Vector::Zero(b.size());
          t0 = std::chrono::steady_clock::now();
          const JacobiPreconditioner jac(a1);
          const double setup = seconds_since(t0);
          t0 = std::chrono::steady_clock::now();
          const SolveReport r = conjugate_gradient(op, b, x, opt, &jac);
          row("CG, Jacobi", setup, seconds_since(t0), r.iterations, r.residual, 0);
        }
        {
          Vector x = Vector::Zero(b.size());
          t0 = std::chrono::steady_clock::now();
          const SolveReport r = conjugate_gradient(op, b, x, opt);
          row("CG", 0, seconds_since(t0), r.iterations, r.residual, 0);
        }
      }
  });
  if (status != 0) return status;
  std::printf("wrote %s\n", csv.c_str());
  return 0;
}
