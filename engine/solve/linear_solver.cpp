#include "engine/solve/linear_solver.hpp"

#include <cstdio>
#include <cstring>

#include <omp.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>

#include <stdexcept>

#include "engine/profile.hpp"
#include "engine/solve/conjugate_gradients.hpp"

namespace sinew {

namespace {
// Debian's CHOLMOD runs OpenMP regions in its factorisation and solves. Their threads
// would spin beside TBB's on the same cores; with the calling thread's active levels at 0
// every region runs on that thread alone (an OpenMP ICV, per thread: set on each calling
// thread, cheaply, before each call).
void limit_openmp() {
  if (omp_get_max_active_levels() != 0) omp_set_max_active_levels(0);
}
}  // namespace

LinearSolver::SolveWorkspace::SolveWorkspace() { cholmod_start(&common); }

LinearSolver::SolveWorkspace::~SolveWorkspace() {
  cholmod_free_dense(&x, &common);
  cholmod_free_dense(&y, &common);
  cholmod_free_dense(&e, &common);
  cholmod_finish(&common);
}

namespace {

void report_cholmod_error(int status, const char* file, int line, const char* message) {
  if (status < 0) std::fprintf(stderr, "CHOLMOD error %d: %s (%s:%d)\n", status, message, file, line);
}

// to = from (compressed), into to's arrays where they have the size: no allocation once warm.
void copy_compressed(const SparseMatrix& from, SparseMatrix& to) {
  if (to.rows() != from.rows() || to.cols() != from.cols() || to.nonZeros() != from.nonZeros() ||
      !to.isCompressed() || !from.isCompressed()) {
    to = from;
    to.makeCompressed();
    return;
  }
  std::copy(from.outerIndexPtr(), from.outerIndexPtr() + from.outerSize() + 1, to.outerIndexPtr());
  std::copy(from.innerIndexPtr(), from.innerIndexPtr() + from.nonZeros(), to.innerIndexPtr());
  std::copy(from.valuePtr(), from.valuePtr() + from.nonZeros(), to.valuePtr());
}

}  // namespace

LinearSolver::LinearSolver(const SolverDesc& desc)
    : m_use_cholmod(desc.linear != "pcg"),
      m_desc(desc),
      m_single_precision_preconditioner(desc.stale_factor_precision == "single"),
      m_single(std::make_unique<SolveWorkspace>()),
      m_pcg_cap(desc.pcg_max_iterations) {}

bool LinearSolver::factorize(const SparseMatrix& A) {
  ++m_factorizations;
  m_matrix = &A;
  m_factored_valid = false;
  if (!m_use_cholmod) {
    m_cg.compute(A);
    return true;
  }
  if (!m_analyzed) {
    // Simplicial LDL^T below kSupernodalThreshold (the header says why there); above,
    // supernodal: larger 3D lattices have supernodes big enough for BLAS to win by orders
    // of magnitude, and many-column solves take SupernodalBlockSolve's blocked loops.
    m_cholmod.setMode(A.rows() < kSupernodalThreshold ? Eigen::CholmodLDLt : Eigen::CholmodSupernodalLLt);
    // Supernodal systems up to kNestedDissectionLimit DOFs: AMD and nested dissection
    // (CHOLMOD's NESDIS, on METIS), the one with less fill: nested dissection's balanced
    // elimination tree also lets single solves split over two threads
    // (supernodal_tree_solve.hpp). CHOLMOD's default tries METIS only when AMD's fill is
    // poor, and kept AMD for the 4,068-DOF bunny (774,648 entries against NESDIS's 705,609,
    // and no split worth taking). Above the limit NESDIS's analysis costs too much at every
    // new pattern (a change of the sleeping set): 109 -> 871 ms on a 32k-DOF grid. Set on
    // every analysis: the common outlives patterns of other sizes.
    cholmod_common& common = m_cholmod.cholmod();
    // Errors only: a matrix that is not positive definite (a warning to CHOLMOD) comes back
    // as factorize's false, which every caller handles and counts (curvature_dropped, a
    // retried step); CHOLMOD's own line per failure filled a budgeted run's terminal (80 in
    // 90 frames). Its print level would print warnings as errors: a handler of our own.
    common.print = 0;
    common.error_handler = report_cholmod_error;
    if (A.rows() >= kSupernodalThreshold && A.rows() <= kNestedDissectionLimit) {
      common.nmethods = 2;
      common.method[0].ordering = CHOLMOD_AMD;
      common.method[1].ordering = CHOLMOD_NESDIS;
    } else {
      common.nmethods = 0;  // CHOLMOD's default
    }
    m_cholmod.analyzePattern(A);
    m_block_solve = SupernodalBlockSolve{};  // a new symbolic factor, maybe at the same address
    m_tree_solve = SupernodalTreeSolve{};
    m_analyzed = true;
  }
  if (m_keep_factored) copy_compressed(A, m_factored);
  limit_openmp();
  m_cholmod.factorize(A);
  m_factored_valid = m_keep_factored && m_cholmod.info() == Eigen::Success;
  return m_cholmod.info() == Eigen::Success;
}

bool LinearSolver::holds_factor_of(const SparseMatrix& A) const {
  if (!m_factored_valid || !m_use_cholmod || !A.isCompressed() || A.rows() != m_factored.rows() ||
      A.cols() != m_factored.cols() || A.nonZeros() != m_factored.nonZeros())
    return false;
  const auto same = [](const auto* a, const auto* b, Eigen::Index n) {
    return n == 0 || std::memcmp(a, b, static_cast<size_t>(n) * sizeof(*a)) == 0;
  };
  // Bit for bit (memcmp: -0.0 differs from 0.0, as it may in the factor's round-off).
  // Values first: a matrix that changed usually differs within the first entries.
  return same(A.valuePtr(), m_factored.valuePtr(), A.nonZeros()) &&
         same(A.outerIndexPtr(), m_factored.outerIndexPtr(), A.outerSize() + 1) &&
         same(A.innerIndexPtr(), m_factored.innerIndexPtr(), A.nonZeros());
}

long LinearSolver::factor_entries() const {
  const cholmod_factor* L = m_use_cholmod && m_analyzed ? m_cholmod.factor() : nullptr;
  if (!L) return 0;
  return static_cast<long>(L->is_super ? L->xsize : L->nzmax);
}

bool LinearSolver::honours_wanted_rows() const {
  const cholmod_factor* L = m_use_cholmod && m_analyzed ? m_cholmod.factor() : nullptr;
  return L && L->is_super;
}

void LinearSolver::set_pcg_cap(int cap) {
  m_pcg_cap = IterationCaps::effective(m_desc.pcg_max_iterations, cap);
}

int LinearSolver::solve(const VecX& b, VecX& x, FactorUse use) {
  ++m_solves;
  if (m_use_cholmod) {
    x.resize(b.size());
    const bool single = use == FactorUse::Preconditioner && m_single_precision_preconditioner;
    if (single ? single_precision_solve(b.data(), x.data()) : tree_solve(b.data(), x.data())) {
      m_last_residual = 0;
      return 1;
    }
    // cholmod_solve2 into kept buffers: no allocation once they have b's size.
    SolveWorkspace& ws = *m_single;
    solve_into(ws, b.data(), static_cast<int>(b.size()), 1, static_cast<int>(b.size()));
    x = Eigen::Map<const VecX>(static_cast<const double*>(ws.x->x), b.size());
    m_last_residual = 0;
    return 1;
  }
  if (!m_matrix) throw std::logic_error("LinearSolver::solve before factorize on the PCG path");
  const auto start = std::chrono::steady_clock::now();
  const JacobiCg::Result result = m_cg.solve(*m_matrix, b, x, m_desc.pcg_tolerance, m_pcg_cap);
  m_last_residual = result.error;
  m_pcg_totals.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++m_pcg_totals.solves;
  m_pcg_totals.iterations += result.iterations;
  if (!result.converged) ++m_pcg_totals.unconverged;
  return result.iterations;
}

int LinearSolver::solve_preconditioned(const SparseMatrix& A, const VecX& b, VecX& x, double tolerance,
                                      int max_iterations, double scale) {
  VecX &r = m_residual, &z = m_preconditioned, &p = m_search, &q = m_product;
  const double target = tolerance * std::max(b.norm(), scale);
  x.setZero(b.size());
  r = b;
  if (r.norm() <= target) return 0;
  int iterations = 0;
  // A is a step matrix (Newton's H): it has the system pattern's node blocks.
  const CgEnd end = conjugate_gradients(
      [&](const VecX& in, VecX& out) { multiply_node_blocked(A, in, out); }, x, r, z, p, q, max_iterations,
      [&](const VecX& from, VecX& to) { solve(from, to, FactorUse::Preconditioner); },
      [&](const VecX& residual) { return residual.norm() <= target; }, iterations);
  return end == CgEnd::Converged ? iterations : -1;
}

const cholmod_factor* LinearSolver::tree_solvable_factor() {
  const cholmod_factor* L = m_cholmod.factor();
  if (!L || !L->is_super) return nullptr;
  if (!m_tree_solve.analysed_for(*L)) m_tree_solve.analyse(*L);
  return m_tree_solve.ordered() ? L : nullptr;
}

bool LinearSolver::tree_solve(const double* b, double* x) {
  const cholmod_factor* L = tree_solvable_factor();
  if (!L) return false;
  m_tree_solve.solve(*L, b, x);
  return true;
}

bool LinearSolver::single_precision_solve(const double* b, double* x) {
  const cholmod_factor* L = tree_solvable_factor();
  if (!L) return false;
  if (m_single_values_of != m_factorizations) {
    const double* values = static_cast<const double*>(L->x);
    m_single_values.assign(values, values + L->xsize);  // one pass, allocation-free once sized
    m_single_values_of = m_factorizations;
  }
  m_tree_solve.solve(*L, m_single_values.data(), b, x);
  return true;
}

void LinearSolver::solve_into(SolveWorkspace& ws, const double* columns, int rows, int cols, int stride) {
  limit_openmp();
  cholmod_dense b{};  // a view of the columns: cholmod_solve2 only reads it
  b.nrow = rows;
  b.d = stride;
  b.ncol = cols;
  b.nzmax = static_cast<size_t>(stride) * cols;
  b.x = const_cast<double*>(columns);
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, m_cholmod.factor(), &b, nullptr, &ws.x, nullptr, &ws.y, &ws.e, &ws.common))
    throw std::runtime_error("CHOLMOD solve failed (out of memory)");
}

const double* LinearSolver::solve_block(SolveWorkspace& ws, const double* columns, int stride) {
  solve_into(ws, columns, ws.rows, kSolveBlock, stride);
  return static_cast<const double*>(ws.x->x);
}

void LinearSolver::prepare_block_workspaces(int rows) {
  const size_t slots = static_cast<size_t>(tbb::this_task_arena::max_concurrency());
  while (m_block_workspaces.size() < slots) m_block_workspaces.push_back(std::make_unique<SolveWorkspace>());
  const cholmod_factor* L = m_cholmod.factor();
  const bool super = L->is_super;
  const int supernodes = super ? static_cast<int>(L->nsuper) : 0;
  for (const auto& ws : m_block_workspaces) {
    // A new symbolic factor of the same size may have other supernodes: sized again.
    if (ws->rows == rows && ws->super == super && ws->supernodes == supernodes) continue;
    ws->rows = rows;
    ws->super = super;
    ws->supernodes = supernodes;
    if (super) {
      m_block_solve.prepare(ws->supernodal);
      continue;
    }
    if (ws->padded.rows() < rows) ws->padded.resize(rows, kSolveBlock);  // kept at the largest size
    ws->padded.topRows(rows).setZero();
    solve_block(*ws, ws->padded.data(), static_cast<int>(ws->padded.rows()));  // sizes CHOLMOD's buffers
  }
}

namespace {
SupernodalBlockSolve::ColumnRows column_rows(const LinearSolver::ColumnPattern* pattern, int c) {
  if (!pattern) return {};
  return {pattern->rows.data() + pattern->start[c], pattern->start[c + 1] - pattern->start[c]};
}
}  // namespace

void LinearSolver::solve_many(const Eigen::Ref<const MatX>& B, Eigen::Ref<MatX> X, const std::vector<int>* wanted_rows,
                              const ColumnPattern* pattern) {
  if (X.rows() != B.rows() || X.cols() != B.cols()) throw std::logic_error("LinearSolver::solve_many: X is not B's size");
  if (m_use_cholmod) {
    m_solves += B.cols();
    cholmod_factor* L = m_cholmod.factor();
    const int n = static_cast<int>(B.rows());
    if (B.cols() == 0) return;
    // CHOLMOD's supernodal solve calls BLAS, which Debian's serial OpenBLAS does not allow
    // from two threads at once (wrong results, measured) and the pthread build serialises:
    // supernodal blocks go through SupernodalBlockSolve, which calls neither.
    if (L->is_super && B.cols() == 1) {
      // One column: the tree solve (split over the elimination tree or in order), or, with
      // supernodes out of order, CHOLMOD's own solve (its BLAS-2 kernels beat the block
      // loops at width 1).
      if (tree_solve(B.data(), X.data())) return;
      SolveWorkspace& ws = *m_single;
      solve_into(ws, B.data(), n, 1, n);
      X = Eigen::Map<const MatX>(static_cast<const double*>(ws.x->x), n, 1);
      return;
    }
    if (L->is_super && !m_block_solve.analysed_for(*L)) m_block_solve.analyse(*L);
    const char* wanted = nullptr;
    if (L->is_super && wanted_rows) {
      m_block_solve.mark_wanted(*wanted_rows, m_wanted);
      wanted = m_wanted.data();
    }
    prepare_block_workspaces(n);
    const int count = static_cast<int>(B.cols());
    // Supernodal: columns in the order of their first nonzero in the factor's order, so that
    // a block's columns share elimination-tree paths and its forward pass skips more. The
    // order depends on B alone: X is the same for any thread count.
    std::vector<int>& order = m_column_order;
    order.resize(count);
    for (int c = 0; c < count; ++c) order[c] = c;
    if (L->is_super) {
      m_column_start.resize(count);
      for (int c = 0; c < count; ++c) {
        const SupernodalBlockSolve::ColumnRows rows = column_rows(pattern, c);
        m_column_start[c] = m_block_solve.first_position(B.col(c).data(), pattern ? &rows : nullptr);
      }
      // std::sort with the index as tie-break: the stable order without stable_sort's buffer.
      std::sort(order.begin(), order.end(), [&](int a, int b) {
        return m_column_start[a] != m_column_start[b] ? m_column_start[a] < m_column_start[b] : a < b;
      });
    }
    // Supernodal blocks of up to kSolveBlock columns, and at least two blocks from two
    // columns on, so that a few columns still keep two cores busy; the split depends on
    // the count alone (bit-identical X for any thread count).
    const int block_width = L->is_super ? std::clamp((count + 1) / 2, 1, kSolveBlock) : kSolveBlock;
    const int blocks = (count + block_width - 1) / block_width;
    // Task k owns workspace k and solves blocks k, k + P, ...: no workspace is shared, whatever
    // thread (or arena slot) runs the task.
    const int tasks = std::min<int>(blocks, static_cast<int>(m_block_workspaces.size()));
    if (L->is_super) {
      // Straight from B's columns into X's: no copy through a padded block (with several
      // bodies a column's solve touches its own body's part of L, and n-long copies,
      // zero padding and write-backs were as costly as the solve).
      tbb::parallel_for(0, tasks, [&](int task) {
        SolveWorkspace& ws = *m_block_workspaces[task];
        std::array<const double*, kSolveBlock> b{};
        std::array<double*, kSolveBlock> x{};
        std::array<SupernodalBlockSolve::ColumnRows, kSolveBlock> rows{};
        for (int block = task; block < blocks; block += tasks) {
          const int first = block * block_width;
          const int width = std::min<int>(block_width, count - first);
          for (int j = 0; j < width; ++j) {
            b[j] = B.col(order[first + j]).data();
            x[j] = X.col(order[first + j]).data();
            rows[j] = column_rows(pattern, order[first + j]);
          }
          m_block_solve.solve(*L, b.data(), x.data(), width, ws.supernodal, wanted, pattern ? rows.data() : nullptr);
        }
      });
      return;
    }
    tbb::parallel_for(0, tasks, [&](int task) {
      SolveWorkspace& ws = *m_block_workspaces[task];
      const int stride = static_cast<int>(ws.padded.rows());
      for (int block = task; block < blocks; block += tasks) {
        const int first = block * block_width;
        const int width = std::min<int>(block_width, count - first);
        for (int j = 0; j < width; ++j) ws.padded.col(j).head(n) = B.col(order[first + j]);
        if (width < kSolveBlock) ws.padded.topRightCorner(n, kSolveBlock - width).setZero();
        // CHOLMOD solves every block kSolveBlock wide: its buffers keep their size.
        const Eigen::Map<const MatX> solution(solve_block(ws, ws.padded.data(), stride), n, kSolveBlock);
        for (int j = 0; j < width; ++j) X.col(order[first + j]) = solution.col(j);
      }
    });
    return;
  }
  // PCG: column by column from zero, through kept vectors (no allocation once warm).
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    m_column_b = B.col(c);
    m_column_x.setZero(B.rows());
    solve(m_column_b, m_column_x);
    X.col(c) = m_column_x;
  }
}

}  // namespace sinew
