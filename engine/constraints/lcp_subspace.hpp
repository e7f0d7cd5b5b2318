#pragma once
// Subspace minimisation between projected Gauss-Seidel sweeps (lcp_pgs.hpp), after
// Silcowitz, Niebe and Erleben, "Projected Gauss-Seidel subspace minimization for
// interactive rigid body dynamics" (2010).
//
// PGS finds which rows sit on a bound within a few sweeps, but converges on the others at a
// rate set by W's conditioning: slow for strain limits, whose rows on neighbouring tets
// share nodes (up to 18 rows on a tet's 12 DOFs, 42 with the pair cuts, so W is singular and its non-zero
// spectrum wide). A subspace step takes the rows strictly inside fixed bounds (strain and
// contact normal rows with lambda > 0, energy rows; friction rows keep theirs, as their box
// follows the normal's lambda) as the free set F, the other multipliers held, and solves
//   W_FF d = -w_F    (w = W lambda + c)
// by conjugate gradients, which needs only products with W, stopping where the CG path
// meets a bound (as MPRGP does, Dostal and Schoeberl 2005): each CG step lowers the LCP's
// quadratic f(lambda) = 1/2 lambda^T W lambda + c^T lambda on the free rows, so the
// truncated path ends feasible and lower.
// With the free set right and CG converged within its iterations, one step lands on the
// solution: w_F = 0 and PGS's next sweep meets its tolerance. W singular is no obstacle:
// for rows of a consistent solution -w_F lies in W_FF's range, and CG stops at a direction
// of (numerically) zero curvature.
#include <algorithm>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/core/scratch_matrix.hpp"
#include "engine/core/types.hpp"

namespace sinew {

// Kept between calls: a warm step allocates nothing. Vectors over the free set F.
struct SubspaceScratch {
  std::vector<int> free;
  ScratchMatrix storage;  // the vectors below, columns of one kept matrix
  void reserve(int rows) {
    free.reserve(rows);
    storage.view(rows, kVectors);
  }
  static constexpr int kVectors = 6;
};

// A CG direction p with p^T W p below this times p^T diag(W) p lies in W_FF's null space up
// to round-off (W's entries carry relative errors near 1e-16 times its largest).
constexpr double kNullCurvature = 1e-10;
// CG stops once r^T D^-1 r has fallen below this fraction of its start (D = diag(W_FF)).
constexpr double kSubspaceCgReduction = 1e-8;

// out_a = sum_b W(rows_a, rows_b) x_b for a W held as a dense matrix (multiply_rows of the
// dense operators).
inline void principal_block_product(const Eigen::Ref<const MatX>& W, const std::vector<int>& rows,
                                    const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) {
  out.setZero();
  for (std::size_t b = 0; b < rows.size(); ++b)
    for (std::size_t a = 0; a < rows.size(); ++a) out[a] += W(rows[a], rows[b]) * x[b];
}

// One subspace step on lambda (rows.lambda) for the operator W of solve_pgs, right after a
// sweep (W.w(i) current). W must also provide multiply_rows(F, x, out): out_a =
// sum_b W(F_a, F_b) x_b, at a cost of |F| columns, not m. Returns the products it took.
template <typename Operator, typename Rows>
int subspace_step(Operator& W, Rows& rows, Eigen::Map<VecX> lambda, int max_cg_iterations, SubspaceScratch& s) {
  const int m = rows.size();
  s.reserve(m);
  s.free.clear();
  for (int i = 0; i < m; ++i)
    if (W.diagonal(i) > 0 && rows.normal_row[i] < 0 && lambda[i] > rows.lo[i] && lambda[i] < rows.hi[i])
      s.free.push_back(i);
  const int n = static_cast<int>(s.free.size());
  if (n == 0) return 0;
  // Sized by m, not n: storage then grows only with the table, as the solver's other buffers.
  Eigen::Map<MatX> columns = s.storage.view(m, SubspaceScratch::kVectors);
  auto column = [&](int k) { return columns.col(k).head(n); };
  auto w = column(0), r = column(1), z = column(2), p = column(3), q = column(4), d = column(5);
  for (int a = 0; a < n; ++a) w[a] = W.w(s.free[a]);
  // CG on W_FF d = -w_F, preconditioned with W's diagonal (rows of different kinds differ
  // in scale by orders of magnitude: m/s for contacts, 1/s for strains).
  const auto precondition = [&] {
    for (int a = 0; a < n; ++a) z[a] = r[a] / W.diagonal(s.free[a]);
  };
  int products = 0;
  d.setZero();
  r = -w;
  precondition();
  p = z;
  double rz = r.dot(z);
  const double stop = kSubspaceCgReduction * rz;
  for (int it = 0; it < max_cg_iterations && rz > stop; ++it) {
    W.multiply_rows(s.free, p, q);
    ++products;
    const double curvature = p.dot(q);
    double scale = 0;  // p^T D p
    for (int a = 0; a < n; ++a) scale += p[a] * p[a] * W.diagonal(s.free[a]);
    // No curvature: along p, f is flat (or falls linearly for ever where w_F has a null-
    // space part); the bounds, not CG, must stop that.
    if (!(curvature > kNullCurvature * scale)) break;
    const double alpha = rz / curvature;
    // The longest step along p that keeps every free row within its bounds: CG stops
    // where its path meets a bound (f falls all along the path up to alpha, so the
    // truncated step still lowers it); PGS's sweeps then take that row off the free set.
    double reach = alpha;
    for (int a = 0; a < n; ++a) {
      const int i = s.free[a];
      const double at = lambda[i] + d[a];
      if (p[a] < 0) reach = std::min(reach, (rows.lo[i] - at) / p[a]);
      else if (p[a] > 0) reach = std::min(reach, (rows.hi[i] - at) / p[a]);
    }
    d += std::max(reach, 0.0) * p;
    if (reach < alpha) break;
    r -= alpha * q;
    precondition();
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  for (int a = 0; a < n; ++a) {
    const int i = s.free[a];
    lambda[i] = std::clamp(lambda[i] + d[a], rows.lo[i], rows.hi[i]);  // clamp: round-off only
  }
  return products;
}

}  // namespace sinew
