#include "engine/solve/supernodal_block_solve.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "engine/core/cpu_features.hpp"
#include "engine/solve/supernode_kernels_avx2.hpp"
#include "engine/solve/supernode_view.hpp"

namespace sinew {

namespace {

// The passes work on rows of the block (one unknown, every right-hand side), W values each,
// packed (row r at y + W r: a narrow block touches no more memory than it needs), through
// fixed-size maps: Eigen vectorises them and, unlike
// its dynamic-size GEMM and TRSM, never allocates blocking buffers (a warm step allocates
// nothing). Supernode blocks are column-major (leading dimension `height`).
constexpr int kMaxWidth = SupernodalBlockSolve::kMaxWidth;

template <int W>
using Row = Eigen::Map<Eigen::Matrix<double, 1, W>>;

template <int W>
void forward(const SupernodeView& s, double* y, const int* supernode_of, char* nonzero) {
  const auto row = [y](int r) { return Row<W>(y + static_cast<size_t>(r) * W); };
  // The triangle: y_k /= L_kk, then the rows below k within the triangle.
  for (int k = 0; k < s.columns; ++k) {
    const double* column = s.L + static_cast<size_t>(k) * s.height;
    Row<W> yk = row(s.first + k);
    yk *= 1.0 / column[k];
    for (int r = k + 1; r < s.columns; ++r) row(s.first + r).noalias() -= column[r] * yk;
  }
  // The rows below the triangle, two columns of L at a time (half the passes over them).
  int k = 0;
  for (; k + 1 < s.columns; k += 2) {
    const double* c0 = s.L + static_cast<size_t>(k) * s.height;
    const double* c1 = c0 + s.height;
    const Eigen::Matrix<double, 1, W> y0 = row(s.first + k), y1 = row(s.first + k + 1);
    for (int r = s.columns; r < s.height; ++r) row(s.rows[r]).noalias() -= c0[r] * y0 + c1[r] * y1;
  }
  if (k < s.columns) {
    const double* c0 = s.L + static_cast<size_t>(k) * s.height;
    const Eigen::Matrix<double, 1, W> y0 = row(s.first + k);
    for (int r = s.columns; r < s.height; ++r) row(s.rows[r]).noalias() -= c0[r] * y0;
  }
  for (int r = s.columns; r < s.height; ++r) nonzero[supernode_of[s.rows[r]]] = 1;
}

template <int W>
void backward(const SupernodeView& s, double* y) {
  const auto row = [y](int r) { return Row<W>(y + static_cast<size_t>(r) * W); };
  // y_k -= sum over the rows below of L_rk y_r, two columns at a time.
  int k = 0;
  for (; k + 1 < s.columns; k += 2) {
    const double* c0 = s.L + static_cast<size_t>(k) * s.height;
    const double* c1 = c0 + s.height;
    Eigen::Matrix<double, 1, W> a0 = Eigen::Matrix<double, 1, W>::Zero(), a1 = a0;
    for (int r = s.columns; r < s.height; ++r) {
      const Row<W> yr = row(s.rows[r]);
      a0.noalias() += c0[r] * yr;
      a1.noalias() += c1[r] * yr;
    }
    row(s.first + k) -= a0;
    row(s.first + k + 1) -= a1;
  }
  if (k < s.columns) {
    const double* c0 = s.L + static_cast<size_t>(k) * s.height;
    Eigen::Matrix<double, 1, W> a0 = Eigen::Matrix<double, 1, W>::Zero();
    for (int r = s.columns; r < s.height; ++r) a0.noalias() += c0[r] * row(s.rows[r]);
    row(s.first + k) -= a0;
  }
  // The triangle, transposed: last unknown first.
  for (int k = s.columns - 1; k >= 0; --k) {
    const double* column = s.L + static_cast<size_t>(k) * s.height;
    Row<W> yk = row(s.first + k);
    for (int r = k + 1; r < s.columns; ++r) yk.noalias() -= column[r] * row(s.first + r);
    yk *= 1.0 / column[k];
  }
}

// The passes over one supernode: the AVX2 kernels for blocks 4 or more wide where the CPU
// has it (the same bits), else the ones above.
template <int W>
void forward_pass(bool avx2, const SupernodeView& s, double* y, const int* supernode_of, char* nonzero) {
  if constexpr (W % 4 == 0)
    if (avx2) return forward_avx2<W>(s, y, supernode_of, nonzero);
  forward<W>(s, y, supernode_of, nonzero);
}

template <int W>
void backward_pass(bool avx2, const SupernodeView& s, double* y) {
  if constexpr (W % 4 == 0)
    if (avx2) return backward_avx2<W>(s, y);
  backward<W>(s, y);
}

template <int W>
void run_passes(const cholmod_factor& L, double* y, const int* supernode_of, const int* parent, char* nonzero,
                const char* wanted, int& visited) {
  const int nsuper = static_cast<int>(L.nsuper);
  // Forward: L y = P b; a supernode the block has not reached is zero and is skipped.
  const bool avx2 = use_avx2();  // read once: both passes take the same kernels
  for (int s = 0; s < nsuper; ++s)
    if (nonzero[s]) forward_pass<W>(avx2, supernode_view(L, s), y, supernode_of, nonzero);
  // Backward: L^T z = y, from the roots down. z_s = 0 where y_s = 0 (not reached) and z is 0
  // on every row below s's triangle (ancestors found zero): the block's columns then belong to
  // other parts of the tree, e.g. to other bodies, whose blocks of L are apart. nonzero[s] now
  // says whether z_s may be nonzero.
  // Unwanted supernodes are skipped: no wanted one is below them (wanted is closed upwards).
  for (int s = nsuper - 1; s >= 0; --s) {
    if (wanted && !wanted[s]) {
      nonzero[s] = 0;
      continue;
    }
    // Its rows below the triangle lie in its ancestors, all of them among its parent's rows
    // or in the parent itself (the elimination tree's row structure): they are zero unless
    // the parent's solution may be nonzero.
    if (!nonzero[s]) {
      if (parent[s] < 0 || !nonzero[parent[s]]) continue;
      nonzero[s] = 1;
    }
    backward_pass<W>(avx2, supernode_view(L, s), y);
    ++visited;
  }
}

}  // namespace

void SupernodalBlockSolve::analyse(const cholmod_factor& L) {
  if (!L.is_super || !L.is_ll || L.itype != CHOLMOD_INT || L.xtype != CHOLMOD_REAL)
    throw std::logic_error("SupernodalBlockSolve: needs a real supernodal LL^T factor with int indices");
  m_factor = &L;
  m_n = static_cast<int>(L.n);
  const int* super = static_cast<const int*>(L.super);
  const int* perm = static_cast<const int*>(L.Perm);
  m_supernode_of.assign(m_n, 0);
  m_position.assign(m_n, 0);
  for (int k = 0; k < m_n; ++k) m_position[perm[k]] = k;
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s)
    for (int k = super[s]; k < super[s + 1]; ++k) m_supernode_of[k] = s;
  // A supernode's parent holds its first row below the triangle.
  m_parent.assign(L.nsuper, -1);
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s) {
    const SupernodeView view = supernode_view(L, s);
    if (view.height > view.columns) m_parent[s] = m_supernode_of[view.rows[view.columns]];
  }
}

void SupernodalBlockSolve::mark_wanted(const std::vector<int>& rows, std::vector<char>& wanted) const {
  wanted.assign(m_parent.size(), 0);
  for (const int row : rows) wanted[m_supernode_of[m_position[row]]] = 1;
  // Parents come after their children in CHOLMOD's supernode order: one sweep closes the set.
  for (size_t s = 0; s < m_parent.size(); ++s)
    if (wanted[s] && m_parent[s] >= 0) wanted[m_parent[s]] = 1;
}

void SupernodalBlockSolve::prepare(Workspace& ws) const {
  ws.y.resize(static_cast<size_t>(m_n) * kMaxWidth);
  ws.nonzero.resize(m_factor ? m_factor->nsuper : 0);
}

int SupernodalBlockSolve::first_position(const double* column, const ColumnRows* candidates) const {
  int first = m_n;
  if (candidates) {
    for (int r = 0; r < candidates->count; ++r)
      if (const int i = candidates->rows[r]; column[i] != 0) first = std::min(first, m_position[i]);
    return first;
  }
  for (int i = 0; i < m_n; ++i)
    if (column[i] != 0) first = std::min(first, m_position[i]);
  return first;
}

void SupernodalBlockSolve::solve(const cholmod_factor& L, const double* B, int ldb, double* X, int ldx, int width,
                                 Workspace& ws, const char* wanted) const {
  if (width < 1 || width > kMaxWidth) throw std::logic_error("SupernodalBlockSolve: width out of range");
  std::array<const double*, kMaxWidth> b{};
  std::array<double*, kMaxWidth> x{};
  for (int c = 0; c < width; ++c) {
    b[c] = B + static_cast<size_t>(c) * ldb;
    x[c] = X + static_cast<size_t>(c) * ldx;
  }
  solve(L, b.data(), x.data(), width, ws, wanted);
}

void SupernodalBlockSolve::solve(const cholmod_factor& L, const double* const* b, double* const* x, int width,
                                 Workspace& ws, const char* wanted, const ColumnRows* candidates) const {
  if (width < 1 || width > kMaxWidth) throw std::logic_error("SupernodalBlockSolve: width out of range");
  const int n = m_n;
  const int* perm = static_cast<const int*>(L.Perm);
  if (ws.y.size() != static_cast<size_t>(n) * kMaxWidth || ws.nonzero.size() != L.nsuper) prepare(ws);
  // Kernels for 1, 2, 4, 8 and 16 columns; a narrower block is padded with zero columns.
  const int padded = width <= 2 ? width : width <= 4 ? 4 : width <= 8 ? 8 : kMaxWidth;
  double* y = ws.y.data();
  std::fill(ws.nonzero.begin(), ws.nonzero.end(), 0);
  ws.backward_supernodes = 0;
  // y = P b: zeroed, then each column's nonzeros placed, read in b's own order (the columns
  // are sparse: a row's stencil, a node's unit vectors); a supernode holding a nonzero
  // starts the forward pass there. Reading b in the factor's order cost a random access
  // per row and column, most of them zeros (the default demo: 11 % of its run).
  std::fill_n(y, static_cast<size_t>(n) * padded, 0.0);
  const auto place = [&](const double* column, int i, int c) {
    if (column[i] != 0) {
      const int k = m_position[i];
      y[static_cast<size_t>(k) * padded + c] = column[i];
      ws.nonzero[m_supernode_of[k]] = 1;
    }
  };
  for (int c = 0; c < width; ++c) {
    if (candidates) {  // only where the caller says its nonzeros are
      for (int r = 0; r < candidates[c].count; ++r) place(b[c], candidates[c].rows[r], c);
    } else {
      for (int i = 0; i < n; ++i) place(b[c], i, c);
    }
  }
  if (padded == 1) run_passes<1>(L, y, m_supernode_of.data(), m_parent.data(), ws.nonzero.data(), wanted, ws.backward_supernodes);
  else if (padded == 2) run_passes<2>(L, y, m_supernode_of.data(), m_parent.data(), ws.nonzero.data(), wanted, ws.backward_supernodes);
  else if (padded == 4) run_passes<4>(L, y, m_supernode_of.data(), m_parent.data(), ws.nonzero.data(), wanted, ws.backward_supernodes);
  else if (padded == 8) run_passes<8>(L, y, m_supernode_of.data(), m_parent.data(), ws.nonzero.data(), wanted, ws.backward_supernodes);
  else run_passes<kMaxWidth>(L, y, m_supernode_of.data(), m_parent.data(), ws.nonzero.data(), wanted, ws.backward_supernodes);
  // x = P^T z: zero outside the supernodes the backward pass worked on (wanted ones only),
  // each entry written once (zeroing all of x first wrote most of it twice: 6 % of the
  // default demo's instructions).
  const int* super = static_cast<const int*>(L.super);
  for (int s = 0; s < static_cast<int>(L.nsuper); ++s)
    if (ws.nonzero[s]) {
      for (int k = super[s]; k < super[s + 1]; ++k)
        for (int c = 0; c < width; ++c) x[c][perm[k]] = y[static_cast<size_t>(k) * padded + c];
    } else {
      for (int k = super[s]; k < super[s + 1]; ++k)
        for (int c = 0; c < width; ++c) x[c][perm[k]] = 0.0;
    }
}

}  // namespace sinew
