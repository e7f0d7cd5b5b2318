#pragma once
// The SPD solve of backward Euler (paper 000, eq. 19): CHOLMOD (symbolic analysis once per
// topology, numeric factorisation per step) or Jacobi-preconditioned CG warm-started from
// the previous velocities. Chosen by the scene's solver.linear.
#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <memory>

#include "engine/assembly/system_pattern.hpp"
#include "engine/core/types.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

class LinearSolver {
 public:
  static constexpr int kSupernodalThreshold = 1000;  // DOFs
  explicit LinearSolver(const SolverDesc& desc);
  // Numeric factorisation (CHOLMOD) or preconditioner setup (PCG). The first call, and
  // any call after reset_pattern(), also runs the symbolic analysis. False if A is not SPD.
  bool factorize(const SparseMatrix& A);
  // Solves A x = b. PCG starts from the x passed in. Returns iterations (1 for CHOLMOD).
  int solve(const VecX& b, VecX& x);
  // Solves A X = B column by column (CHOLMOD: one call with all columns).
  void solve_many(const MatX& B, MatX& X);
  void reset_pattern() { m_analyzed = false; }
  bool uses_cholmod() const { return m_use_cholmod; }
  double last_residual() const { return m_last_residual; }
  // Work counters since construction (StepWork): factorize() calls and right-hand sides solved.
  long factorizations() const { return m_factorizations; }
  long solves() const { return m_solves; }

 private:
  bool m_use_cholmod = true;
  bool m_analyzed = false;
  double m_last_residual = 0;
  long m_factorizations = 0, m_solves = 0;
  SolverDesc m_desc;
  Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> m_cholmod;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper,
                           Eigen::DiagonalPreconditioner<double>>
      m_pcg;
  const SparseMatrix* m_matrix = nullptr;
};

}  // namespace sinew
