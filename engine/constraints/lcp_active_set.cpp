#include "engine/constraints/lcp_active_set.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/math/add_scaled.hpp"
#include "engine/math/transpose_columns.hpp"

namespace sinew {

namespace {
// Sweeps on A between checks of the rows outside it (a check costs about one sweep over
// every row on T).
constexpr int kRoundSweeps = 32;
constexpr int kPlainSweeps = 4;
// The fewest sweeps left for which W_AA is formed (below, the plain sweeps go on).
constexpr int kMinActiveSweeps = 4;
}  // namespace

void ActiveSetPgs::Block::start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c) {
  for (int p = 0; p < m_size; ++p) m_w[m_slot[p]] = c[p];
  add_scaled_nonzero(m_w, m_size, m_size, lambda.data(), [&](int p) { return column(p); });
}

void ActiveSetPgs::Block::changed(int p, double delta) { add_scaled(m_w, column(p), delta, m_size); }

void ActiveSetPgs::Block::changed4(const int* p, const double* delta) {
  const double* columns[4] = {column(p[0]), column(p[1]), column(p[2]), column(p[3])};
  add_scaled4(m_w, columns, delta, m_size);
}

void ActiveSetPgs::Block::multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x,
                                        Eigen::Ref<VecX> out) const {
  // The free rows' columns of W_AA (contiguous), four a pass, into a product over all of
  // A's slots; the free rows' entries gathered. |F| columns, not |A|.
  Eigen::Map<VecX> product(m_product, m_size);
  product.setZero();
  const int n = static_cast<int>(rows.size());
  add_scaled_nonzero(m_product, m_size, n, x.data(), [&](int b) { return column(rows[b]); });
  for (int a = 0; a < n; ++a) out[a] = product[m_slot[rows[a]]];
}

void ActiveSetPgs::add_one(int i) {
  if (m_position[i] >= 0) return;
  m_position[i] = static_cast<int>(m_active.size());
  m_active.push_back(i);
}

void ActiveSetPgs::add(const RowTable& rows, int i) {
  // A friction row's box follows its normal's multiplier: a contact's rows join together.
  const int normal = rows.normal_row[i] >= 0 ? rows.normal_row[i] : i;
  add_one(normal);
  for (int k = m_friction_begin[normal]; k < m_friction_begin[normal + 1]; ++k) add_one(m_friction_rows[k]);
}

void ActiveSetPgs::extend_block(const Delassus& W, int rows) {
  const int n = static_cast<int>(m_active.size());
  if (n == m_formed) return;
  if (n > m_stride) {
    // A larger leading dimension: the formed columns move up, the last first, so that no
    // column is overwritten before it moved (each lands at or above where it was).
    const int stride = std::min(std::max(n, 2 * m_stride), rows);  // n <= rows
    double* data = m_block.view(stride, stride).data();
    for (int b = m_formed - 1; b >= 0; --b)
      std::memmove(data + static_cast<std::size_t>(b) * stride, data + static_cast<std::size_t>(b) * m_stride,
                   sizeof(double) * m_formed);
    m_stride = stride;
  }
  double* data = m_block.data();
  const int first = m_formed;
  // New columns of T first (each by one task), then held transposed (row d of m_transposed
  // holds T(d, A_b) at slot b), so that a row of W_AA is a few runs of 3-term updates over
  // contiguous slots (add_row_entries) rather than an entry at a time, each a gather over the
  // row's stencil from a column of T. Rows were formed (A grows) against the earlier slots;
  // each row now gets its entries against the new slots beyond its own, each entry summed by
  // one task in entry()'s order (the same bits for any thread count), then mirrored.
  tbb::parallel_for(tbb::blocked_range<int>(first, n, 8), [&](const tbb::blocked_range<int>& range) {
    for (int b = range.begin(); b < range.end(); ++b) W.ensure_column(m_active[b]);
  });
  const int k3 = W.touched_dofs();
  // Slots up to n <= min(rows, k3): A holds table rows, and solve() falls back to T beyond k3.
  const int slots = std::min(rows, k3);
  double* transposed = m_transposed.view(slots, k3).data();
  m_new_columns.resize(n);
  for (int b = first; b < n; ++b) m_new_columns[b] = W.built_column(m_active[b]);
  tbb::parallel_for(tbb::blocked_range<int>(first, n, 32), [&](const tbb::blocked_range<int>& range) {
    transpose_columns(m_new_columns.data() + range.begin(), range.end() - range.begin(), k3,
                      transposed + range.begin(), slots);
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4), [&](const tbb::blocked_range<int>& range) {
    for (int a = range.begin(); a < range.end(); ++a) {
      const int from = std::max(first, a + 1);
      if (from >= n) continue;
      double* row = data + static_cast<std::size_t>(a) * m_stride;  // column a: entries (b, a) = (a, b)
      std::fill(row + from, row + n, 0.0);
      W.add_row_entries(m_active[a], transposed + from, slots, n - from, row + from);
    }
  });
  for (int b = first; b < n; ++b) {
    double* column = data + static_cast<std::size_t>(b) * m_stride;
    column[b] = W.diagonal(m_active[b]);  // as solve_pgs on W divides by it
    for (int a = 0; a < b; ++a) column[a] = data[static_cast<std::size_t>(a) * m_stride + b];
  }
  m_formed = n;
}

PgsResult ActiveSetPgs::solve(Delassus& W, const Eigen::Ref<const VecX>& c, const Eigen::Ref<const VecX>& weight,
                              RowTable& rows, int max_iterations, double tolerance, int subspace_interval) {
  assert(!W.dense());  // entry() reads T and the stencils of the factored form
  const int m = rows.size();
  PgsResult result;
  m_rounds = 0;
  m_active.clear();
  m_position.assign(m, -1);
  m_sorted.resize(m);
  // Sized by the table, as the solver's other buffers: they grow only with it.
  for (std::vector<int>* v : {&m_active, &m_order, &m_slot, &m_reduced.normal_row, &m_friction_rows}) v->reserve(m);
  for (std::vector<double>* v : {&m_reduced.lo, &m_reduced.hi, &m_reduced.mu, &m_reduced.lambda}) v->reserve(m);
  m_new_columns.reserve(m);
  m_vectors.view(m, 4);
  m_formed = 0;
  // Each normal row's friction rows, grouped by normal (counting sort).
  m_friction_begin.assign(m + 1, 0);
  for (int i = 0; i < m; ++i)
    if (rows.normal_row[i] >= 0) ++m_friction_begin[rows.normal_row[i] + 1];
  for (int i = 0; i < m; ++i) m_friction_begin[i + 1] += m_friction_begin[i];
  m_friction_rows.resize(m_friction_begin[m]);
  m_friction_cursor.assign(m_friction_begin.begin(), m_friction_begin.end() - 1);
  for (int i = 0; i < m; ++i)
    if (rows.normal_row[i] >= 0) m_friction_rows[m_friction_cursor[rows.normal_row[i]]++] = i;
  if (max_iterations <= 0) return result;
  // The first sweeps over every row on T: most LCPs of a settled scene end within them (the
  // side-pressed finger's median LCP), where forming W_AA would cost more than it saves;
  // the rest start from rows that PGS has already sorted into A or out of it.
  result = solve_pgs(W, c, weight, rows, std::min(max_iterations, kPlainSweeps), tolerance, subspace_interval);
  if (result.residual <= tolerance || result.iterations >= max_iterations) return result;
  // Every row with a multiplier (the warm start) is in A from the start, whatever its W_ii:
  // solve_pgs leaves such a row's multiplier as it is, and it still acts on the others.
  for (int i = 0; i < m; ++i)
    if (rows.lambda[i] != 0) add(rows, i);
  const Eigen::Map<const VecX> lambda(rows.lambda.data(), m);
  // Rounds: the rows outside A (multiplier 0) checked against w = T lambda + c, every row
  // that violates its condition at all added (not only those past the tolerance: A then
  // holds the rows plain PGS would have moved, and the flat finger's SQP took 222 iterations
  // over frames 10-110 against 253 when only rows past the tolerance joined, 227 with plain
  // PGS), and at most kRoundSweeps sweeps on A; the first check right after the plain sweeps,
  // then whenever A meets the tolerance and every kRoundSweeps sweeps, so that A is not
  // solved for long without rows it will need.
  double inner_residual = 0;
  for (bool solved = false;; solved = true) {
    W.start(lambda, c);
    double outside = 0;
    m_outside_violated.clear();
    for (int i = 0; i < m; ++i) {
      if (m_position[i] >= 0 || !(W.diagonal(i) > 0)) continue;
      double lo, hi;
      pgs_bounds(rows, lambda, i, lo, hi);
      const double residual = natural_residual(0.0, W.w(i), W.diagonal(i), lo, hi) * weight[i];  // lambda_i = 0
      outside = std::max(outside, residual);
      if (residual > 0) m_outside_violated.push_back(i);
    }
    if (solved) {
      result.residual = std::max(inner_residual, outside);
      if (result.residual <= tolerance || result.iterations >= max_iterations) break;
    }
    for (const int i : m_outside_violated) add(rows, i);
    const int n = static_cast<int>(m_active.size());
    if (n == 0) {  // no row has force or violates its condition: solved
      result.residual = outside;
      break;
    }
    // On T for the rest where A does not pay: A past T's height (an update on W_AA would cost
    // more than one on T, and W_AA outgrow T), or too few sweeps left to repay forming W_AA.
    if (n > W.touched_dofs() || (!solved && max_iterations - result.iterations < kMinActiveSweeps)) {
      const PgsResult rest =
          solve_pgs(W, c, weight, rows, max_iterations - result.iterations, tolerance, subspace_interval);
      result.iterations += rest.iterations;
      result.subspace_products += rest.subspace_products;
      result.residual = rest.residual;
      break;
    }
    ++m_rounds;
    extend_block(W, m);
    // Swept in the rows' own order (as solve_pgs on W would: the order of the table, tets
    // then contacts), whatever order they joined in: position p is row m_order[p], whose
    // entries sit in W_AA's slot m_position[row].
    m_order.assign(m_active.begin(), m_active.end());
    std::sort(m_order.begin(), m_order.end());
    m_slot.resize(n);
    for (int p = 0; p < n; ++p) m_slot[p] = m_position[m_order[p]], m_sorted[m_order[p]] = p;
    m_reduced.lo.resize(n), m_reduced.hi.resize(n), m_reduced.mu.resize(n), m_reduced.lambda.resize(n);
    m_reduced.normal_row.resize(n);
    Eigen::Map<MatX> vectors = m_vectors.view(n, 4);
    auto c_a = vectors.col(0), weight_a = vectors.col(1), w = vectors.col(2);
    for (int p = 0; p < n; ++p) {
      const int i = m_order[p];
      m_reduced.lo[p] = rows.lo[i], m_reduced.hi[p] = rows.hi[i], m_reduced.mu[p] = rows.mu[i];
      m_reduced.lambda[p] = rows.lambda[i];
      m_reduced.normal_row[p] = rows.normal_row[i] >= 0 ? m_sorted[rows.normal_row[i]] : -1;
      c_a[p] = c[i], weight_a[p] = weight[i];
    }
    Block block(m_block.data(), n, m_stride, m_slot.data(), w.data(), vectors.col(3).data());
    const PgsResult inner = solve_pgs(block, c_a, weight_a, m_reduced,
                                      std::min(max_iterations - result.iterations, kRoundSweeps), tolerance,
                                      subspace_interval);
    result.iterations += inner.iterations;
    result.subspace_products += inner.subspace_products;
    inner_residual = inner.residual;
    for (int p = 0; p < n; ++p) rows.lambda[m_order[p]] = m_reduced.lambda[p];
  }
  return result;
}

}  // namespace sinew
