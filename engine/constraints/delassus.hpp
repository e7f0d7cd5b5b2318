#pragma once
// The LCP matrix W = J H^-1 J^T of paper 000, eq. 23, for the rows of a RowTable, from
// G = H^-1 on the touched nodes (touched_inverse.hpp): with T = G Jc^T (3k x m, k touched
// nodes), W = Jc T. Projected Gauss-Seidel (lcp_pgs.hpp) needs W's diagonal, w = W lambda + c
// and its update when one lambda_i changes, which this provides in the cheaper of two forms:
// - dense (m <= 3k): W formed once (m^2 x stencil), w kept and updated by a column of W (m);
// - factored (m > 3k, e.g. strain limits: up to 18 rows per tet, 42 with the pair cuts on 3 DOFs per node):
//   u = T lambda kept (3k), w_i = c_i + Jc_i u over the row's stencil, update by a column
//   of T (3k). No m x m matrix at all, and a column of T only for the rows whose multiplier
//   is or becomes non-zero (W_ii from G's blocks on the stencil).
// Or, when the rows touch so many nodes not solved yet that one solve per row is cheaper
// (hex energy rows span 8 nodes, embedded contacts too), directly from Y = H^-1 J^T.
#include <algorithm>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/constraints/touched_inverse.hpp"
#include "engine/core/scratch_matrix.hpp"
#include "engine/core/types.hpp"
#include "engine/math/add_scaled.hpp"

namespace sinew {

class Delassus {
 public:
  // Rows' stencils on touched nodes: `local_node[n]` is the position in `inverse` of global
  // node n, or -1 (fixed nodes, which carry no velocity). Every free stencil node must have
  // columns in `inverse`. In the factored form the columns of T are built from `inverse` on
  // first use: it must stay unchanged (no require() or reset()) while this W is used. The
  // const members that read T (multiply, multiply_rows, matrix) may build columns, so they
  // are not to be called from two threads at once.
  void build(const RowTable& rows, const std::vector<int>& local_node, const TouchedInverse& inverse);
  // W = J Y (dense form); `free_index[n]` is the free index of global node n or -1, Y is
  // 3 free x m.
  void build_direct(const RowTable& rows, const std::vector<int>& free_index, const MatX& Y);
  // The same with column i of Y at columns[i] (3 free values; row_column_cache.hpp). With
  // `node_body` (global node -> body), entries between rows on no common body are 0 without
  // a sum: H couples no two bodies (no element spans two; build_model checks it), so Y_j is
  // zero on the bodies row j does not touch.
  // With `generations` (row_column_cache.hpp: partial columns), W_ij is read from the
  // column of the later generation, the one right on the other row's stencil.
  void build_direct(const RowTable& rows, const std::vector<int>& free_index, const std::vector<const double*>& columns,
                    const std::vector<int>* node_body = nullptr, const std::vector<long>* generations = nullptr);
  // Entries W_ij (i >= j) the last build_direct knew were 0 without a sum, and those it
  // summed (tests; counted on demand, O(m^2)).
  long zero_entries() const;
  long summed_entries() const { return static_cast<long>(size()) * (size() + 1) / 2 - zero_entries(); }

  // Whether the last build was build_direct with m rows: after RowColumnCache reports the
  // same columns for the same rows, its W stands as it is.
  bool built_direct(int m) const { return m_direct && size() == m; }

  int size() const { return static_cast<int>(m_diagonal.size()); }
  // T's height, 3 x the touched nodes (factored form; 0 after build_direct).
  int touched_dofs() const { return m_k3; }
  // Columns of T built so far (factored form: those of rows with a multiplier at build(),
  // then each row's at its first change; tests).
  int built_columns() const { return static_cast<int>(std::count(m_column_built.begin(), m_column_built.end(), 1)); }
  bool dense() const { return m_dense; }
  double diagonal(int i) const { return m_diagonal[i]; }
  // The interface of solve_pgs: start from lambda; w_i for the current lambda; lambda_i
  // changed by delta. w and changed are defined below, inline: PGS calls them twice and
  // once per row and sweep (the pressed flat finger: 45 % of its instructions).
  void start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c);
  double w(int i) const;
  void changed(int i, double delta);
  // Factored form (lcp_active_set.hpp): builds column i of T unless built (one task per
  // column at a time), and W_ij = J_i T_j over row i's stencil, column j built.
  void ensure_column(int i) const {
    if (!m_dense && !m_column_built[i]) build_column(i);
  }
  double entry(int i, int j) const;
  // Factored form: column i of T, built (ensure_column).
  const double* built_column(int i) const { return T().col(i).data(); }
  // Adds row i's stencil terms of W_{i, j_b} to out[b], b < count, one term at a time in
  // entry()'s order, where column j_b of T is held transposed: entry b of row d of
  // `transposed` (leading dimension `stride`) is T(d, j_b). On out = +0 the result is entry(i,
  // j_b) bit for bit (lcp_active_set.cpp forms W_AA so, a row of it at a time).
  void add_row_entries(int i, const double* transposed, Eigen::Index stride, int count, double* out) const;
  // out = W lambda (the stored or factored W; no m x m matrix is formed).
  void multiply(const Eigen::Ref<const VecX>& lambda, Eigen::Ref<VecX> out) const;
  // The same on a subset of rows (solve_pgs's subspace steps): out_a = sum_b W(rows_a,
  // rows_b) x_b, over |rows| columns of W or T.
  void multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) const;
  // W itself (tests, and lcp_residual): the stored W in the dense forms, formed from T in
  // the factored one.
  MatX matrix() const;

 private:
  // Views of the kept storage (scratch_matrix.hpp: no allocation once warm).
  Eigen::Map<MatX> T() const { return m_T_storage.view(m_k3, size()); }
  Eigen::Map<MatX> W() const { return m_W_storage.view(size(), size()); }
  Eigen::Map<VecX> c() const { return m_c_storage.vector(size()); }
  Eigen::Map<VecX> state() const { return m_state_storage.vector(m_dense ? size() : m_k3); }
  // W = Jc T: entry (i, j), i >= j, over row i's stencil and column j of T; then mirrored.
  void form_W_from_T(Eigen::Ref<MatX> W) const;
  // Factored form: column i of T, built on first use (build_column).
  void build_column(int i) const;
  const double* column(int i) const;
  // start + Jc_i u over row i's stencil (u: 3k values in touched-node order), each node's term
  // added in stencil order.
  double stencil_dot(int i, const double* u, double start) const;
  // u = T lambda over the columns whose multiplier is not 0.
  void factored_product(const Eigen::Ref<const VecX>& lambda, Eigen::Map<VecX>& u) const;

  bool m_dense = false;
  bool m_direct = false;  // built by build_direct
  std::vector<uint64_t> m_body_mask;  // build_direct: per row, bit (body mod 64) of each body it touches
  int m_k3 = 0;                       // 3 x touched nodes: T's rows
  std::vector<int> m_begin, m_local;  // rows' stencils in touched-node positions
  std::vector<Vec3> m_jac;
  std::vector<int> m_next_begin, m_next_local;  // build's new stencils, compared with the last
  std::vector<Vec3> m_next_jac;
  long m_G_version = -1;                        // TouchedInverse::version of the last build
  mutable ScratchMatrix m_T_storage;  // 3k x m: G Jc^T, in the factored form only the columns built
  mutable std::vector<char> m_column_built;  // per row: its column of T is current
  const double* m_G_data = nullptr;          // G of the last build (touched_inverse.hpp), column-major
  Eigen::Index m_G_stride = 0;
  mutable ScratchMatrix m_W_storage;  // dense form only
  std::vector<double> m_diagonal;
  std::vector<const double*> m_columns;  // build_direct from a MatX
  // PGS's hot loop reads through these (set by start(); the storage does not move after).
  const double* m_c_data = nullptr;
  double* m_state_data = nullptr;
  const double* m_columns_data = nullptr;  // W (dense) or T, column-major
  mutable ScratchMatrix m_c_storage, m_state_storage, m_product_storage;  // dense: w; factored: u = T lambda
};

inline double Delassus::stencil_dot(int i, const double* u, double start) const {
  double s = start;
  for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) s += m_jac[e].dot(Eigen::Map<const Vec3>(u + 3 * m_local[e]));
  return s;
}

inline double Delassus::w(int i) const {
  if (m_dense) return m_state_data[i];
  return stencil_dot(i, m_state_data, m_c_data[i]);
}

inline double Delassus::entry(int i, int j) const {
  return stencil_dot(i, m_T_storage.data() + static_cast<std::size_t>(j) * m_k3, 0.0);
}

inline void Delassus::changed(int i, double delta) {
  // W symmetric: column i = row i.
  if (!m_dense && !m_column_built[i]) build_column(i);
  const int n = m_dense ? size() : m_k3;
  add_scaled(m_state_data, m_columns_data + static_cast<std::size_t>(i) * n, delta, n);
}

}  // namespace sinew
