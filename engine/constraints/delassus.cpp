#include "engine/constraints/delassus.hpp"

#include <cassert>

#include "engine/constraints/lcp_subspace.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sinew {

namespace {

// W_ij = entry(i, j) for i >= j, columns in parallel (each entry summed in one order whatever
// the thread count), then W_ji = W_ij: symmetric by construction, as PGS's column updates
// assume, for half the work of the whole matrix.
template <typename Entry>
void fill_symmetric(Eigen::Ref<MatX> W, const Entry& entry) {
  const int m = static_cast<int>(W.rows());
  tbb::parallel_for(tbb::blocked_range<int>(0, m, 4), [&](const tbb::blocked_range<int>& range) {
    for (int j = range.begin(); j < range.end(); ++j)
      for (int i = j; i < m; ++i) W(i, j) = entry(i, j);
  });
  for (int j = 0; j < m; ++j)
    for (int i = j + 1; i < m; ++i) W(j, i) = W(i, j);
}

}  // namespace

void Delassus::build(const RowTable& rows, const std::vector<int>& local_node, const TouchedInverse& inverse) {
  const int m = rows.size();
  m_next_begin.assign(1, 0);
  m_next_local.clear();
  m_next_jac.clear();
  for (int i = 0; i < m; ++i) {
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
      if (const int a = local_node[rows.nodes[e]]; a >= 0) {
        m_next_local.push_back(a);
        m_next_jac.push_back(rows.jac[e]);
      }
    m_next_begin.push_back(static_cast<int>(m_next_local.size()));
  }
  const auto G = inverse.block();
  // Nothing W (or T) is made of changed since the last build: the same G (no reset, no
  // column added) and the rows' stencils and Jacobians bit for bit, as for contacts on a
  // plane held at rest across SQP iterations and steps while G is kept. W, T's built columns
  // and the diagonal then stand (cube_20 at rest: 663 rows, W of 663 x 663 formed anew at
  // every step before).
  const bool stands = !m_direct && size() == m && m_G_version == inverse.version() && m_G_data == G.data() &&
                      m_k3 == 3 * inverse.size() && m_next_begin == m_begin && m_next_local == m_local &&
                      m_next_jac == m_jac;
  if (stands) return;
  m_begin.swap(m_next_begin);
  m_local.swap(m_next_local);
  m_jac.swap(m_next_jac);
  m_G_version = inverse.version();
  m_k3 = 3 * inverse.size();
  m_diagonal.resize(m);  // size() from here on
  m_direct = false;
  m_G_data = G.data();
  m_G_stride = G.outerStride();
  m_dense = m <= m_k3;
  m_column_built.assign(m, 0);
  T();  // T's storage sized before the tasks write into it
  // W_ii from G's blocks on row i's stencil (16 3 x 3 blocks for a tet's 4 nodes), not from
  // T's column: a factored W needs T's column of a row only once its multiplier moves, and
  // most rows near a limit never carry force (the pressed finger: 160 of 520). The columns
  // of rows that start with a multiplier (the warm start) are built here, in parallel,
  // each summed in the same order whatever the thread count; the others when PGS first
  // changes their multiplier (changed, column). A dense W needs every column, and takes
  // its diagonal from W itself.
  tbb::parallel_for(tbb::blocked_range<int>(0, m, 32), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i < range.end(); ++i) {
      if (m_dense) {
        build_column(i);
        continue;
      }
      double d = 0;
      for (int e = m_begin[i]; e < m_begin[i + 1]; ++e)
        for (int f = m_begin[i]; f < m_begin[i + 1]; ++f)
          d += m_jac[e].dot(G.block<3, 3>(3 * m_local[e], 3 * m_local[f]) * m_jac[f]);
      m_diagonal[i] = d;
      if (rows.lambda[i] != 0) build_column(i);
    }
  });
  if (!m_dense) return;
  form_W_from_T(W());
  for (int i = 0; i < m; ++i) m_diagonal[i] = W()(i, i);
}

// Column i of T = G Jc^T from row i alone: 24 x 3k flops, rebuilt at every SQP iteration
// (the rows' Jacobians move).
void Delassus::build_column(int i) const {
  assert(m_G_data && !m_direct);  // G of the last build(), which must still be alive
  const Eigen::Map<const MatX, 0, Eigen::OuterStride<>> G(m_G_data, m_k3, m_k3, Eigen::OuterStride<>(m_G_stride));
  auto column = T().col(i);
  if (m_begin[i] == m_begin[i + 1]) column.setZero();  // no free node: T_i = 0
  // The first node's three columns set T_i, the others add to it (no zeroing pass).
  for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) {
    const int a = 3 * m_local[e];
    const Vec3& j = m_jac[e];
    (e == m_begin[i] ? set_scaled3 : add_scaled3)(column.data(), G.col(a).data(), G.col(a + 1).data(),
                                                  G.col(a + 2).data(), j[0], j[1], j[2], m_k3);
  }
  m_column_built[i] = 1;
}

void Delassus::add_row_entries(int i, const double* transposed, Eigen::Index stride, int count, double* out) const {
  // stencil_dot's s += j . u for each stencil entry in turn, j . u = (j0 u0 + j1 u1) + j2 u2.
  for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) {
    const double* u = transposed + 3 * static_cast<Eigen::Index>(m_local[e]) * stride;
    const Vec3& j = m_jac[e];
    add_scaled3(out, u, u + stride, u + 2 * stride, j[0], j[1], j[2], count);
  }
}

const double* Delassus::column(int i) const {
  if (!m_column_built[i]) build_column(i);
  return T().col(i).data();
}

void Delassus::build_direct(const RowTable& rows, const std::vector<int>& free_index, const MatX& Y) {
  m_columns.resize(rows.size());
  for (int i = 0; i < rows.size(); ++i) m_columns[i] = Y.col(i).data();
  build_direct(rows, free_index, m_columns);
}

void Delassus::build_direct(const RowTable& rows, const std::vector<int>& free_index,
                            const std::vector<const double*>& columns, const std::vector<int>* node_body,
                            const std::vector<long>* generations) {
  const int m = rows.size();
  m_diagonal.resize(m);  // size() from here on
  Eigen::Map<MatX> W = this->W();
  // Bodies as bits mod 64: with more than 64 bodies two may share a bit, which only sums
  // some entries that are 0 anyway.
  m_body_mask.assign(m, node_body ? 0 : ~uint64_t{0});
  if (node_body)
    for (int i = 0; i < m; ++i)
      for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
        if (free_index[rows.nodes[e]] >= 0) m_body_mask[i] |= uint64_t{1} << ((*node_body)[rows.nodes[e]] & 63);
  // W_ij = J_i Y_j over row i's stencil: the creature's 96 rows of 8 nodes each cost 110k
  // multiply-adds a build, at every SQP iteration; the default demo's three creatures,
  // 300-600 rows, a third of that when rows on different bodies are left out.
  fill_symmetric(W, [&](int i, int j) {
    if ((m_body_mask[i] & m_body_mask[j]) == 0) return 0.0;
    if (generations && (*generations)[i] > (*generations)[j]) std::swap(i, j);  // J_i y_j with y_j right on row i
    const double* y = columns[j];
    double s = 0;
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
      if (const int f = free_index[rows.nodes[e]]; f >= 0)
        s += rows.jac[e][0] * y[3 * f] + rows.jac[e][1] * y[3 * f + 1] + rows.jac[e][2] * y[3 * f + 2];
    return s;
  });
  for (int i = 0; i < m; ++i) m_diagonal[i] = W(i, i);
  m_k3 = 0;
  m_dense = true;
  m_direct = true;
  m_G_data = nullptr;
  m_column_built.clear();
}

long Delassus::zero_entries() const {
  if (!m_direct) return 0;
  long zero = 0;
  for (int j = 0; j < size(); ++j)
    for (int i = j; i < size(); ++i) zero += (m_body_mask[i] & m_body_mask[j]) == 0;
  return zero;
}

void Delassus::form_W_from_T(Eigen::Ref<MatX> W) const {
  T();  // sized (entry reads T's storage directly)
  fill_symmetric(W, [&](int i, int j) { return entry(i, j); });
}

void Delassus::multiply(const Eigen::Ref<const VecX>& lambda, Eigen::Ref<VecX> out) const {
  if (m_dense) {
    out.noalias() = W() * lambda;
    return;
  }
  Eigen::Map<VecX> u = m_product_storage.vector(m_k3);
  factored_product(lambda, u);
  for (int i = 0; i < size(); ++i) out[i] = stencil_dot(i, u.data(), 0.0);
}

void Delassus::multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x,
                             Eigen::Ref<VecX> out) const {
  if (m_dense) {
    principal_block_product(W(), rows, x, out);
    return;
  }
  const int n = static_cast<int>(rows.size());
  Eigen::Map<VecX> u = m_product_storage.vector(m_k3);
  u.setZero();
  for (int b = 0; b < n; ++b) add_scaled(u.data(), column(rows[b]), x[b], m_k3);
  for (int a = 0; a < n; ++a) out[a] = stencil_dot(rows[a], u.data(), 0.0);
}

MatX Delassus::matrix() const {
  if (m_dense) return W();
  for (int i = 0; i < size(); ++i) column(i);
  MatX W(size(), size());
  form_W_from_T(W);
  return W;
}

void Delassus::start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c) {
  this->c() = c;
  if (m_dense) {
    // W lambda as the sum of the columns with a multiplier only, then + c: the flat finger's
    // warm starts put force on about a third of the rows, and a product over all of them was
    // 3 % of its step.
    Eigen::Map<VecX> u = state();
    u.setZero();
    const double* w = W().data();
    const Eigen::Index n = size();
    add_scaled_nonzero(u.data(), size(), size(), lambda.data(), [&](int i) { return w + i * n; });
    u += this->c();
  } else {
    Eigen::Map<VecX> u = state();
    factored_product(lambda, u);
  }
  m_c_data = this->c().data();
  m_state_data = state().data();
  m_columns_data = m_dense ? W().data() : T().data();
}

void Delassus::factored_product(const Eigen::Ref<const VecX>& lambda, Eigen::Map<VecX>& u) const {
  // Over the columns with a multiplier only: the others may not be built.
  u.setZero();
  add_scaled_nonzero(u.data(), m_k3, size(), lambda.data(), [&](int i) { return column(i); });
}

}  // namespace sinew
