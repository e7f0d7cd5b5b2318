#include "engine/solve/linear_solver.hpp"

namespace sinew {

LinearSolver::LinearSolver(const SolverDesc& desc)
    : m_use_cholmod(desc.linear != "pcg"), m_desc(desc) {
  m_pcg.setTolerance(desc.pcg_tolerance);
  m_pcg.setMaxIterations(desc.pcg_max_iterations);
}

bool LinearSolver::factorize(const SparseMatrix& A) {
  ++m_factorizations;
  m_matrix = &A;
  if (!m_use_cholmod) {
    m_pcg.compute(A);
    return m_pcg.info() == Eigen::Success;
  }
  if (!m_analyzed) {
    // Simplicial LDL^T factorises the few-thousand-DOF systems of real-time scenes faster
    // than the supernodal path (no BLAS call per supernode); larger 3D lattices have
    // supernodes big enough for BLAS to win by orders of magnitude.
    m_cholmod.setMode(A.rows() < kSupernodalThreshold ? Eigen::CholmodLDLt : Eigen::CholmodSupernodalLLt);
    m_cholmod.analyzePattern(A);
    m_analyzed = true;
  }
  m_cholmod.factorize(A);
  return m_cholmod.info() == Eigen::Success;
}

int LinearSolver::solve(const VecX& b, VecX& x) {
  ++m_solves;
  if (m_use_cholmod) {
    x = m_cholmod.solve(b);
    m_last_residual = 0;
    return 1;
  }
  if (x.size() != b.size()) x.setZero(b.size());
  x = m_pcg.solveWithGuess(b, x);
  m_last_residual = m_pcg.error();
  return static_cast<int>(m_pcg.iterations());
}

void LinearSolver::solve_many(const MatX& B, MatX& X) {
  if (m_use_cholmod) {
    m_solves += B.cols();
    X = m_cholmod.solve(B);
    return;
  }
  X.resize(B.rows(), B.cols());
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    VecX col = VecX::Zero(B.rows());
    solve(B.col(c), col);
    X.col(c) = col;
  }
}

}  // namespace sinew
