#pragma once
// The SPD solve of backward Euler (paper 000, eq. 19): CHOLMOD (symbolic analysis once per
// topology, numeric factorisation per step) or Jacobi-preconditioned CG (jacobi_cg.hpp) from
// the x passed in. Chosen by the scene's solver.linear.
#include <Eigen/CholmodSupport>
#include <memory>
#include <vector>

#include "engine/assembly/system_pattern.hpp"
#include "engine/core/types.hpp"
#include "engine/core/zeroed_columns.hpp"
#include "engine/scene/scene.hpp"
#include "engine/solve/cholmod_memory_pool.hpp"
#include "engine/solve/jacobi_cg.hpp"
#include "engine/solve/supernodal_block_solve.hpp"
#include "engine/solve/supernodal_tree_solve.hpp"

namespace sinew {

class LinearSolver {
 public:
  // DOFs. Below, simplicial LDL^T: a factorisation and a solve or two per step cost less
  // there. Above, the constraint solve's many columns (one per row, or H^-1 on touched
  // nodes) go through SupernodalBlockSolve, 16 columns at a time: the pressed fingers (360
  // DOFs, 500 rows) `sqp_solve` 25-35 % lower, paper 000's beams (378) 30-45 % and its
  // collapse 2-3x faster a step; a 270-DOF beam without constraints 14 % slower (measured
  // 2026-12-04 with supernodal factors everywhere against 1000, docs/ARCHITECTURE.md stage 2).
  static constexpr int kSupernodalThreshold = 300;
  static constexpr int kNestedDissectionLimit = 20000;  // DOFs: AMD or NESDIS up to here (factorize)
  explicit LinearSolver(const SolverDesc& desc);
  // Numeric factorisation (CHOLMOD) or preconditioner setup (PCG). The first call, and
  // any call after reset_pattern(), also runs the symbolic analysis. False if A is not SPD.
  bool factorize(const SparseMatrix& A);
  // What a CHOLMOD solve is for: the step's own matrix (Exact; callers also pass it for a
  // factorisation with the constraints' curvature), or a matrix the factor only
  // approximates (Preconditioner: an earlier step's factorisation), where with solver.stale_factor_precision "single" a supernodal
  // factor's solve reads a float copy of its values (supernodal_tree_solve.hpp).
  enum class FactorUse { Exact, Preconditioner };
  // Solves A x = b. PCG starts from the x passed in. Returns iterations (1 for CHOLMOD).
  int solve(const VecX& b, VecX& x, FactorUse use = FactorUse::Exact);
  // PCG's iteration cap per solve: the scene's pcg_max_iterations, or `cap` when that is
  // lower and positive (the real-time budget's IterationCaps::pcg; 0 restores the scene's).
  void set_pcg_cap(int cap);
  // PCG solves since construction (solver.linear "pcg": solve() and solve_many's columns),
  // their iterations, those stopped at a cap above pcg_tolerance, and their wall time.
  struct PcgTotals {
    long solves = 0, iterations = 0, unconverged = 0;
    double ms = 0;
  };
  const PcgTotals& pcg_totals() const { return m_pcg_totals; }
  // CHOLMOD only: solves A x = b, A full symmetric (both triangles) with the system pattern's
  // node blocks (its products by multiply_node_blocked, which throws std::invalid_argument on
  // other matrices) and not the matrix last factorised, by conjugate gradients preconditioned
  // with that factorisation (FactorUse::Preconditioner: its single-precision copy with
  // solver.stale_factor_precision "single"), from x = 0 until |b - A x| <= tolerance max(|b|, scale). Returns the iterations, or -1 when
  // max_iterations were not enough or A showed no positive curvature along a search direction.
  int solve_preconditioned(const SparseMatrix& A, const VecX& b, VecX& x, double tolerance, int max_iterations,
                           double scale = 0);
  // b - A x at the end of the last solve_preconditioned, as CG's recurrence carried it (not a
  // product formed again): valid until the next call.
  const VecX& preconditioned_residual() const { return m_residual; }
  // Solves A X = B column by column, into X of B's size. CHOLMOD: blocks of columns solved
  // in parallel (one task per workspace, blocks dealt round robin), the split fixed by the
  // column count alone (X is bit-identical for any number of threads). Simplicial factors:
  // cholmod_solve2 on blocks of kSolveBlock (the last one zero-padded). Supernodal factors:
  // SupernodalBlockSolve (no BLAS call, no lock; zero parts of a block skipped in the
  // forward pass, and parts of L whose solution is zero in the backward pass) on blocks of
  // ceil(count / 2) columns, at most kSolveBlock, the columns ordered by their first nonzero
  // in the factor's order, read from B and written into X where they are (no copy); a single
  // column by the tree solve or CHOLMOD. X may be B itself (each block reads its columns of
  // B before writing them), not a view overlapping B's columns otherwise.
  // With `wanted_rows` (rows of X, any order), X needs to be right on those rows only: the
  // supernodal block solves then skip the backward pass below them (X is exact there, bit
  // for bit as without, and zero on the rows the pass skipped); other paths solve in full.
  // With `pattern` (zeroed_columns.hpp: column c's nonzeros lie in rows
  // pattern->rows[pattern->start[c] .. pattern->start[c + 1])), B's columns are read there
  // only (supernodal block solves: right-hand sides of a few non-zeros among thousands of rows).
  using ColumnPattern = ZeroedColumns::Pattern;
  void solve_many(const Eigen::Ref<const MatX>& B, Eigen::Ref<MatX> X, const std::vector<int>* wanted_rows = nullptr,
                  const ColumnPattern* pattern = nullptr);
  // The same, resizing X.
  void solve_many(const MatX& B, MatX& X) {
    X.resize(B.rows(), B.cols());
    solve_many(B, Eigen::Ref<MatX>(X));
  }
  static constexpr int kSolveBlock = SupernodalBlockSolve::kMaxWidth;
  void reset_pattern() { m_analyzed = m_factored_valid = false; }
  bool uses_cholmod() const { return m_use_cholmod; }
  double last_residual() const { return m_last_residual; }
  // Work counters since construction (StepWork): factorize() calls and right-hand sides solved.
  long factorizations() const { return m_factorizations; }
  // With keep_factored_matrix(true), factorize keeps a copy of each matrix it factorises
  // (pattern and values; no allocation once it has the size), and holds_factor_of(A) says
  // whether the last factorisation succeeded and was of A bit for bit, so that its factor is
  // what factorising A again would make: Newton's Hessian at rest, its tet Hessians all kept,
  // is the same matrix step after step (solve_newton.cpp). Off by default (a copy a
  // factorisation).
  void keep_factored_matrix(bool keep) { m_keep_factored = keep; }
  bool holds_factor_of(const SparseMatrix& A) const;
  long solves() const { return m_solves; }
  // Entries stored in the CHOLMOD factor (0 without one): a solve costs about two
  // multiply-adds per entry.
  long factor_entries() const;
  // Whether solve_many's `wanted_rows` can save work (a supernodal CHOLMOD factor; other
  // paths solve in full).
  bool honours_wanted_rows() const;

 private:
  bool m_pool = (install_cholmod_memory_pool(), true);  // before any CHOLMOD call
  bool m_use_cholmod = true;
  bool m_analyzed = false;
  double m_last_residual = 0;
  PcgTotals m_pcg_totals;
  VecX m_residual, m_preconditioned, m_search, m_product;  // solve_preconditioned's, kept
  long m_factorizations = 0, m_solves = 0;
  bool m_keep_factored = false, m_factored_valid = false;
  SparseMatrix m_factored;  // the last matrix factorised, with m_keep_factored
  SolverDesc m_desc;
  bool m_single_precision_preconditioner;  // m_desc.stale_factor_precision == "single"
  // Eigen's wrapper, with the factor exposed for solves from several threads at once.
  struct Cholmod : Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> {
    cholmod_factor* factor() { return m_cholmodFactor; }
    const cholmod_factor* factor() const { return m_cholmodFactor; }
  };
  // A CHOLMOD workspace (its own cholmod_common and solve buffers, reused).
  struct SolveWorkspace {
    SolveWorkspace();
    ~SolveWorkspace();
    SolveWorkspace(const SolveWorkspace&) = delete;
    SolveWorkspace& operator=(const SolveWorkspace&) = delete;
    cholmod_common common;
    cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
    MatX padded;     // simplicial: >= rows x kSolveBlock, a narrower block zero-padded (its leading dimension)
    SupernodalBlockSolve::Workspace supernodal;
    int rows = -1;   // the system size its buffers were made for
    bool super = false;  // ... and whether for a supernodal factor
    int supernodes = 0;  // ... of that many supernodes
  };
  // One workspace per thread the arena may run, all made for the system's size (and the
  // supernodal factor's supernodes) before the blocks run, and every simplicial block solved
  // kSolveBlock wide (the last one padded): CHOLMOD's buffers then never change size, whichever thread takes which task (a thread that first
  // joined after the warm-up, or a block narrower than the one before, used to allocate).
  void prepare_block_workspaces(int rows);
  // cholmod_solve2 of `cols` columns (leading dimension `stride`) into ws's buffers.
  void solve_into(SolveWorkspace& ws, const double* columns, int rows, int cols, int stride);
  // Simplicial factor: X = A^-1 B for kSolveBlock columns; returns X (rows x kSolveBlock,
  // leading dimension rows).
  const double* solve_block(SolveWorkspace& ws, const double* columns, int stride);
  Cholmod m_cholmod;
  SupernodalBlockSolve m_block_solve;  // analysed for the current symbolic factor, or not yet
  SupernodalTreeSolve m_tree_solve;    // the same
  // x = A^-1 b by m_tree_solve when the factor is supernodal: split over two threads where
  // its tree allows, else in order on one (sinew_bench_single_solve: 1.2-1.7x faster than
  // CHOLMOD's solve, whose BLAS may also round differently from CPU to CPU); false (nothing
  // done) when its supernodes are out of order.
  bool tree_solve(const double* b, double* x);
  // The factor, its tree analysed, when it is supernodal with supernodes in order; else null.
  const cholmod_factor* tree_solvable_factor();
  // The same with the factor's values in single precision (the float copy made on the first
  // such solve after each factorisation), split or on one thread; false (nothing done)
  // when the factor is not supernodal or its supernodes are out of order.
  bool single_precision_solve(const double* b, double* x);
  std::vector<float> m_single_values;  // the factor's values as floats, of factorisation...
  long m_single_values_of = -1;        // ... number (m_factorizations), -1: none
  std::vector<int> m_column_order, m_column_start;  // solve_many's, kept
  std::vector<char> m_wanted;                        // solve_many's supernode mask, kept
  std::vector<std::unique_ptr<SolveWorkspace>> m_block_workspaces;
  std::unique_ptr<SolveWorkspace> m_single;  // solve(): one column, its buffers kept
  JacobiCg m_cg;
  int m_pcg_cap = 0;  // iterations per PCG solve in force (set_pcg_cap)
  VecX m_column_b, m_column_x;  // solve_many's columns on the PCG path, kept
  const SparseMatrix* m_matrix = nullptr;
};

}  // namespace sinew
