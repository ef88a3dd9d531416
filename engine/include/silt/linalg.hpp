// The linear-algebra layer: symmetric positive definite systems A x = b, solved through one
// contract, `solve(b, x) -> SolveReport`, by
//   - conjugate gradients, on any linear operator (matrix-free) or on a sparse matrix, with no
//     preconditioner, a Jacobi one, or a Cholesky factor of a (possibly older) matrix;
//   - a direct sparse Cholesky solve (CHOLMOD, supernodal, fill-reducing ordering),
// so that each can be checked against the others and their costs compared. The lubricated paste
// solves its resistance matrix with them, the fluid its pressure Poisson equation.
//
// Determinism: every reduction (dot products, norms) is summed in fixed blocks, in a fixed order,
// whatever the number of threads, and the sparse product gives each row to one thread; CHOLMOD
// runs on a serial BLAS. A solve gives bitwise the same result on 1, 2 or 4 threads.
//
// Failures are reports, never NaN: a system that is not positive definite, an operator with no
// progress (breakdown), an iteration limit, or a non-finite input or result each have a status
// and a message naming what happened.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace silt::linalg {

using Vector = Eigen::VectorXd;
// Compressed sparse columns, both triangles stored (a symmetric matrix as a whole).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

enum class SolveStatus {
  kConverged,      // relative residual |b - A x| / |b| <= tolerance
  kMaxIterations,  // the iteration limit came first
  kNotPositive,    // the matrix (or the operator along a search direction) is not positive definite
  kNotFinite,      // a NaN or an infinity in b, in the matrix, or appearing during the solve
  kStagnated,      // CG's recurrence reached the tolerance, the true residual stayed above it after
                   // restarts from it: the round-off of an ill-conditioned system, whatever the limit
};
const char* status_name(SolveStatus s);

struct SolveReport {
  int iterations = 0;   // CG iterations; 0 for a direct solve
  double residual = 0;  // relative residual |b - A x| / |b| of the returned x (0 when b = 0)
  SolveStatus status = SolveStatus::kConverged;
  std::string message;  // what went wrong, "" when converged
  int64_t column = -1;  // kNotPositive from a factorisation: the column (unknown) where it failed
  bool ok() const { return status == SolveStatus::kConverged; }
};

struct SolveOptions {
  double tolerance = 1e-10;  // on the relative residual
  int max_iterations = 1000;
};

// y = A x for a symmetric positive definite A.
class LinearOperator {
 public:
  virtual ~LinearOperator() = default;
  virtual int64_t size() const = 0;
  virtual void apply(const Vector& x, Vector& y) const = 0;
};

// z = M^-1 r, M symmetric positive definite and close to A.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void apply(const Vector& r, Vector& z) const = 0;
};

// A matrix-free operator from a function.
class FunctionOperator final : public LinearOperator {
 public:
  FunctionOperator(int64_t n, std::function<void(const Vector&, Vector&)> f) : n_(n), f_(std::move(f)) {}
  int64_t size() const override { return n_; }
  void apply(const Vector& x, Vector& y) const override { f_(x, y); }

 private:
  int64_t n_;
  std::function<void(const Vector&, Vector&)> f_;
};

// A symmetric sparse matrix (compressed) as an operator: the product in parallel, rows in fixed
// blocks, each row read as its column.
class SparseOperator final : public LinearOperator {
 public:
  explicit SparseOperator(const SparseMatrix& a);  // keeps a reference: a must outlive it
  int64_t size() const override { return a_.rows(); }
  void apply(const Vector& x, Vector& y) const override;

 private:
  const SparseMatrix& a_;
};

// M = diag(A).
class JacobiPreconditioner final : public Preconditioner {
 public:
  explicit JacobiPreconditioner(const SparseMatrix& a);
  void apply(const Vector& r, Vector& z) const override;
  // The first diagonal entry that is not a positive finite number (its inverse taken as 1), -1
  // when none: where the matrix is not positive definite (or not finite).
  int64_t first_bad() const { return first_bad_; }
  double first_bad_value() const { return first_bad_value_; }

 private:
  Vector inv_diag_;
  int64_t first_bad_ = -1;
  double first_bad_value_ = 0;
};

// The vectors conjugate_gradient works in, kept by a caller that solves again and again (a time
// step's solves) so that no call allocates; sized on first use.
struct CgWorkspace {
  Vector r, z, p, ap;
  // Whether z is M^-1 r for the r left at the end (the last call iterated): the preconditioned
  // residual, an estimate of the solution's error that a caller may read for free.
  bool z_of_r = false;
};

// Conjugate gradients from x (the initial guess; the solution on return). M and ws may be null.
SolveReport conjugate_gradient(const LinearOperator& a, const Vector& b, Vector& x, const SolveOptions& opt,
                               const Preconditioner* m = nullptr, CgWorkspace* ws = nullptr);

// The memory a Cholesky factor will take, from CHOLMOD's symbolic analysis of a pattern alone (its
// fill-reducing ordering and supernodal structure, as CholeskyFactor::analyze makes them): for
// the matrix whose every entry of `pattern` (symmetric, both triangles) stands for a dense
// block x block block, the supernodes' values scaled by block^2 (a block's rows and columns
// stay together in the ordering: they have the same pattern). Cheap: no values, no numerical
// factorisation, block^2 times fewer entries than the matrix itself.
struct FactorSize {
  int64_t entries = 0;   // values of the factor (the supernodes' rectangles)
  int64_t integers = 0;  // its integer pattern and permutation
  int64_t update = 0;    // the numerical factorisation's largest update matrix (values)
  // Bytes: the factor held, and the factorisation's peak beyond it.
  double factor_bytes() const { return 8.0 * static_cast<double>(entries) + 4.0 * static_cast<double>(integers); }
  double workspace_bytes() const { return 8.0 * static_cast<double>(update); }
};
FactorSize block_factor_size(const SparseMatrix& pattern, int block);

// How silt's triangular solves with a factor are shared among threads: the parallel tasks (the
// elimination tree's subtrees), and the shares of the factor's entries in them and in the top's
// supernodes whose blocks are shared (the rest of the top runs on one thread). `alone`: the
// supernodes alone in their trees (no parent, no child), solved together in one more task and
// counted in in_tasks.
struct SolveSplit {
  int64_t tasks = 0, alone = 0;
  double in_tasks = 0, shared = 0;
};

// A sparse Cholesky factor L L^T = A (CHOLMOD, supernodal). The symbolic analysis (fill-reducing
// ordering and the factor's pattern) is kept and reused by factorize() while the pattern of A does
// not change; analyze() starts over. A factor serves as a direct solver and as a preconditioner.
class CholeskyFactor final : public Preconditioner {
 public:
  CholeskyFactor();
  ~CholeskyFactor() override;
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;

  // The ordering and the pattern of the factor for the pattern of `a` (values unused): CHOLMOD's
  // fill-reducing ordering, or `order` instead (order[k] the column eliminated k-th; CHOLMOD
  // postorders it, as it does its own).
  void analyze(const SparseMatrix& a, const std::vector<int>* order = nullptr);
  bool analysed_for(const SparseMatrix& a) const;  // the held analysis is of a's pattern
  // The elimination order of the held analysis (empty before one).
  std::vector<int> order() const;
  // Numerical factorisation of `a` (analyzed first if the pattern is new). Returns kConverged, or
  // kNotPositive naming the column where positivity failed, or kNotFinite.
  SolveReport factorize(const SparseMatrix& a);
  bool ready() const;  // a successful factorisation is held
  // x = A^-1 b with the held factor; kNotFinite when b or x is not finite. The triangular solves
  // are silt's (linalg/supernodal_solve.hpp: the elimination tree's independent subtrees and the
  // rows and columns of its large separators on several threads, the same bits on any number),
  // or CHOLMOD's own on one thread after use_cholmod_solve(true), the reference they are
  // measured against.
  SolveReport solve(const Vector& b, Vector& x) const;
  void use_cholmod_solve(bool on) { cholmod_solve_ = on; }
  // As a preconditioner (apply()), the factor's values rounded to single precision (the factor
  // held, from now, and every factor made after): its triangular solves read half the bytes, the
  // sums stay in double. solve() stays exact. A factor whose diagonal a float cannot hold to its
  // relative precision is applied in double (applies_single() says which).
  void set_single_preconditioner(bool on);
  bool applies_single() const;
  // How silt's solves with the held factor are shared among threads (all zero: CHOLMOD's solve
  // is used).
  SolveSplit solve_split() const;
  void apply(const Vector& r, Vector& z) const override;
  // Bytes the numerical factor takes (known after analyze()), entries of L.
  int64_t factor_bytes() const;
  int64_t factor_entries() const;
  // The analysed factor's size as block_factor_size gives it (block 1): what an estimate is
  // checked against.
  FactorSize size() const;
  int64_t analyses() const { return analyses_; }
  int64_t factorizations() const { return factorizations_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  SolveReport solve(const Vector& b, Vector& x, bool single) const;
  int64_t analyses_ = 0, factorizations_ = 0;
  bool cholmod_solve_ = false, single_ = false;
};

// A two-level preconditioner around another one, M (a Cholesky factor of an earlier matrix): the
// columns of W span the directions where A has moved away from the matrix M was made from (the
// normals of the stiffest connections of a paste, which turn as the grains roll, and whose
// resistance is so large that a small turn changes A by more than the rest of it); on their span
// the solve is exact, through E = W^T A W, and M serves the rest. The balancing preconditioner
// (Mandel 1993; in the notation of Tang, Nabben, Vuik and Erlangga 2009):
//   P = Q + (I - Q A) M^-1 (I - A Q),  Q = W E^-1 W^T,
// symmetric positive definite whenever M is, so plain PCG runs on it. An application costs one of
// M, two products with A W (kept from the setup, with as many columns as W) and two solves with
// E's factor.
//
// E's fill-reducing ordering (METIS on these patterns) costs about what its factorisation does,
// and a paste's contacts change by a few a step. A caller that names W's columns by keys (a
// contact's direction) has E ordered from the last setup's order instead (OrderMemory): the
// columns it held keep their order, a new one goes after the latest of its neighbours in E, and
// a fresh ordering is made only when that one fills the factor in more than kOrderFillSlack
// times the last fresh ordering did, or when fewer than half the columns are old.
//
// And E's weak couplings may be dropped (set_drop): an entry with |E_cd| < drop sqrt(E_cc E_dd)
// is removed and its size added to E_cc and E_dd. The E factorised, E~, is then E plus a positive
// semi-definite matrix, and P stays symmetric positive definite (x^T P x = 0 asks W^T x = 0, then
// x^T M^-1 x = 0) but is exact on W's span only to about `drop`. On a paste's contacts the
// couplings through other grains' lubrication are 1e-5 of the contacts' own and fill E's factor
// in: dropping them makes it 3 times smaller for the same iterations.
class CoarseCorrection final : public Preconditioner {
 public:
  struct OrderMemory {
    std::vector<int64_t> keys;  // the last setup's columns by key, in E's elimination order
    double fill = 0;            // the factor's entries over E's lower triangle's, at the last fresh ordering
  };
  static constexpr double kOrderFillSlack = 1.1;

  // E = W^T A W, held to a relative 1e-10 above its diagonal (so that dependent columns of W, a
  // self-stressed cluster of contacts, leave it definite), and its factor; W is taken (w is left
  // with the previous one), A W kept, m kept by reference. `keys`, one per column of W: order E
  // from the memory (above); null: CHOLMOD's ordering whenever E's pattern is new. Not ok when E
  // could not be factorised: apply() then applies M alone.
  SolveReport setup(const SparseMatrix& a, SparseMatrix& w, const Preconditioner& m,
                    const std::vector<int64_t>* keys = nullptr);
  void apply(const Vector& r, Vector& z) const override;
  int64_t columns() const { return w_.cols(); }
  bool ready() const { return ready_; }
  void set_drop(double drop) { drop_ = drop; }  // 0: E exact
  // The order kept between setups: what a caller saves so that a restored sequence orders E, and
  // so solves, to the same bits. A memory other than the one held (a restored or replayed state)
  // has the next setup analyse E from it, even for the pattern analysed last.
  const OrderMemory& order_memory() const { return memory_; }
  void set_order_memory(OrderMemory m);
  int64_t fresh_orderings() const { return fresh_; }  // analyses of E with CHOLMOD's own ordering
  int64_t kept_orderings() const { return kept_; }    // analyses of E from the memory
  // Bytes held: W, A W and the factor of E.
  int64_t bytes() const {
    return (w_.nonZeros() + aw_.nonZeros()) * static_cast<int64_t>(sizeof(double) + sizeof(int)) + e_.factor_bytes();
  }

 private:
  const Preconditioner* m_ = nullptr;
  SparseMatrix w_, aw_;
  CholeskyFactor e_;
  bool ready_ = false;
  OrderMemory memory_;
  bool memory_replaced_ = false;  // E's held analysis is not the memory's
  int64_t fresh_ = 0, kept_ = 0;
  double drop_ = 0;
  void analyze_e(const SparseMatrix& e, const std::vector<int64_t>* keys);
  mutable Vector c_, ec_, q_, y_;
};

// How a system is solved: the choices whose costs the benchmarks compare.
enum class Method {
  kCg,         // CG, Jacobi preconditioner
  kFactorPcg,  // CG preconditioned by a Cholesky factor of an earlier matrix, refactorised when the
               // iterations pass a threshold or every `refactor_every` solves
  kDirect,     // a Cholesky factorisation and solve every time
};
const char* method_name(Method m);

struct SolverSettings {
  Method method = Method::kFactorPcg;
  SolveOptions options;
  int refactor_iterations = 20;  // kFactorPcg: refactorise after a solve that took more
  int refactor_every = 0;        // kFactorPcg: and at least every N solves (0: never forced)
  double coarse_drop = 0;        // kFactorPcg: CoarseCorrection::set_drop of the coarse correction
  bool single_factor = false;    // kFactorPcg: the factor applied in single precision (CholeskyFactor)
};

// The columns of a CoarseCorrection's W, and a key naming each (or none): what a caller makes
// for each solve.
struct CoarseSpace {
  CoarseSpace(SparseMatrix columns = {}, std::vector<int64_t> names = {}) : keys(std::move(names)) {
    w.swap(columns);  // Eigen's sparse matrices have no move
  }
  SparseMatrix w;
  std::vector<int64_t> keys;  // empty, or one per column of w
};

// A sequence of solves of slowly changing matrices (one per time step), warm-started from the
// previous solution by the caller's x.
class SpdSolver {
 public:
  explicit SpdSolver(SolverSettings s = {});
  ~SpdSolver();
  SpdSolver(const SpdSolver&) = delete;
  SpdSolver& operator=(const SpdSolver&) = delete;

  // Solves a x = b from x. `pattern_changed`: the sparsity of a differs from the last call's
  // (connections made or broken), so a stored factor cannot precondition it. A b whose largest
  // entry is below 2^-200 (the paste under a pressure of 1e-200) is solved scaled by a power of
  // two, b and x alike, which changes no bit but keeps CG's products of residuals (squares of b's
  // scale) from underflowing to 0: such a b read as zero, and x as 0. (A b beyond 2^200 is left to
  // overflow, and its solve to fail naming the loads: forces so large overflow further on anyway.)
  SolveReport solve(const SparseMatrix& a, const Vector& b, Vector& x, bool pattern_changed);
  const SolverSettings& settings() const { return s_; }
  void set_settings(const SolverSettings& s) {
    s_ = s;
    factor_.set_single_preconditioner(s.single_factor);
  }
  int64_t refactorizations() const { return factor_.factorizations(); }
  int64_t analyses() const { return factor_.analyses(); }
  const CholeskyFactor& factor() const { return factor_; }
  void forget_factor();  // the next kFactorPcg solve factorises first
  // kFactorPcg: whether a factor is held for the next solve, how many solves it has served, and
  // (through on_factor) each matrix it is made from: what a caller saves so that a restored
  // sequence preconditions, and so iterates, to the same bits (restore_factor).
  bool factor_valid() const { return factor_valid_; }
  int solves_since_factor() const { return solves_since_factor_; }
  void set_solves_since_factor(int n) { solves_since_factor_ = n; }
  std::function<void(const SparseMatrix&)> on_factor;
  // kFactorPcg: the matrix to factorise when a factor is due, instead of the system's own (a
  // sparser approximation of it, cheaper to factorise and to apply); null: the system's.
  std::function<SparseMatrix()> factor_source;
  SolveReport restore_factor(const SparseMatrix& source, int solves_since_factor);
  // kFactorPcg: W of a CoarseCorrection around the factor, made for each solve (the directions
  // where the factor goes stale first); null, no columns, or more than a quarter of the unknowns:
  // the factor alone. A corrected solve that fails is done again with a fresh factor alone.
  std::function<CoarseSpace()> coarse_space;
  int64_t coarse_columns() const { return coarse_columns_; }  // of the last solve
  // Solves that a factor applied in single precision left short, finished in double.
  int64_t double_retries() const { return double_retries_; }
  const CoarseCorrection& coarse() const { return coarse_; }
  void set_coarse_order(CoarseCorrection::OrderMemory m) { coarse_.set_order_memory(std::move(m)); }
  // An estimate of the error of x after a solve of a x = b: dx = M^-1 (b - a x), M the
  // preconditioner the solve used last (the factor, Jacobi's diagonal), or its CG's last
  // preconditioned residual when that is of this x, taken the length along it that best cancels
  // the residual (one product with a): M need not be a to scale (a factor of an earlier matrix
  // under another viscosity). The direct method leaves no preconditioner: dx = 0, its solve being
  // refined to round-off.
  void error_estimate(const SparseMatrix& a, const Vector& b, const Vector& x, Vector& dx);

 private:
  SolveReport solve_scaled(const SparseMatrix& a, const Vector& b, Vector& x, bool pattern_changed);

  SolverSettings s_;
  CholeskyFactor factor_;
  bool factor_valid_ = false;
  int solves_since_factor_ = 0;
  int64_t coarse_columns_ = 0, double_retries_ = 0;
  int last_exponent_ = 0;                   // the power of two b was solved scaled by, last
  const Preconditioner* last_m_ = nullptr;  // the preconditioner of the last CG (this object's)
  CgWorkspace cg_;
  Vector estimate_r_, estimate_ad_;  // error_estimate's residual (when CG left none) and a dx, kept
  CoarseCorrection coarse_;
};

}  // namespace silt::linalg
