#include "engine/constraints/delassus.hpp"

namespace sinew {

void Delassus::build(const RowTable& rows, const std::vector<int>& local_node, const TouchedInverse& inverse) {
  const int m = rows.size();
  const int k3 = 3 * inverse.size();
  m_begin.assign(1, 0);
  m_local.clear();
  m_jac.clear();
  for (int i = 0; i < m; ++i) {
    for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
      if (const int a = local_node[rows.nodes[e]]; a >= 0) {
        m_local.push_back(a);
        m_jac.push_back(rows.jac[e]);
      }
    m_begin.push_back(static_cast<int>(m_local.size()));
  }
  const auto G = inverse.block();
  m_T.setZero(k3, m);
  for (int i = 0; i < m; ++i) {
    auto column = m_T.col(i);
    for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) {
      const int a = 3 * m_local[e];
      const Vec3& j = m_jac[e];
      column += G.col(a) * j[0] + G.col(a + 1) * j[1] + G.col(a + 2) * j[2];
    }
  }
  m_diagonal.resize(m);
  for (int i = 0; i < m; ++i) {
    double d = 0;
    for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) d += m_jac[e].dot(m_T.col(i).segment<3>(3 * m_local[e]));
    m_diagonal[i] = d;
  }
  m_dense = false;
  if (m <= k3) {
    m_W = matrix();
    m_dense = true;
  }
}

void Delassus::build_direct(const RowTable& rows, const std::vector<int>& free_index, const MatX& Y) {
  std::vector<const double*> columns(rows.size());
  for (int i = 0; i < rows.size(); ++i) columns[i] = Y.col(i).data();
  build_direct(rows, free_index, columns);
}

void Delassus::build_direct(const RowTable& rows, const std::vector<int>& free_index,
                            const std::vector<const double*>& columns) {
  const int m = rows.size();
  m_W.resize(m, m);
  for (int j = 0; j < m; ++j) {
    const double* y = columns[j];
    for (int i = 0; i < m; ++i) {
      double s = 0;
      for (int e = rows.begin[i]; e < rows.begin[i + 1]; ++e)
        if (const int f = free_index[rows.nodes[e]]; f >= 0)
          s += rows.jac[e][0] * y[3 * f] + rows.jac[e][1] * y[3 * f + 1] + rows.jac[e][2] * y[3 * f + 2];
      m_W(i, j) = s;
    }
  }
  m_W = 0.5 * (m_W + m_W.transpose()).eval();
  m_diagonal.resize(m);
  for (int i = 0; i < m; ++i) m_diagonal[i] = m_W(i, i);
  m_T.resize(0, 0);
  m_dense = true;
}

MatX Delassus::matrix() const {
  if (m_T.cols() != size()) return m_W;  // built directly
  const int m = size();
  MatX W(m, m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      double s = 0;
      for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) s += m_jac[e].dot(m_T.col(j).segment<3>(3 * m_local[e]));
      W(i, j) = s;
    }
  // Symmetric in exact arithmetic (G is symmetric); PGS's column updates assume it.
  return 0.5 * (W + W.transpose());
}

void Delassus::start(const VecX& lambda, const VecX& c) {
  m_c = c;
  if (m_dense) m_state.noalias() = m_W * lambda + c;
  else m_state.noalias() = m_T * lambda;
}

double Delassus::w(int i) const {
  if (m_dense) return m_state[i];
  double s = m_c[i];
  for (int e = m_begin[i]; e < m_begin[i + 1]; ++e) s += m_jac[e].dot(m_state.segment<3>(3 * m_local[e]));
  return s;
}

void Delassus::changed(int i, double delta) {
  if (m_dense) m_state.noalias() += m_W.col(i) * delta;  // W symmetric: column i = row i
  else m_state.noalias() += m_T.col(i) * delta;
}

}  // namespace sinew
