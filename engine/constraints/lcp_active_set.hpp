#pragma once
// Projected Gauss-Seidel on the rows that carry force, for a factored W (delassus.hpp).
//
// In the factored form a PGS update costs a column of T (3k values, k touched nodes) and each
// row's w_i a gather over its stencil, for every row at every sweep. Strain limits make
// many more rows near a limit than rows with force: the pressed flat finger has ~510 rows on
// 360 DOFs, of which ~160 carry force, and its LCPs take 10-200 sweeps. This solver sweeps
// only the active set A (rows with a multiplier, and the normal and friction rows of their
// contacts) with W_AA formed densely (|A|^2 entries, each J_i T_j over a stencil), at |A| per
// update instead of 3k and no gathers. The first 4 sweeps go over every row on T, as
// solve_pgs's (most LCPs of a settled scene end there, where forming W_AA would cost more
// than it saves). Then the rows outside A (multiplier 0) are checked against w = T lambda + c
// (one product over A's columns of T), right away, whenever A meets the tolerance and every
// 32 sweeps; every row that violates its condition joins A (its entries added to W_AA) for
// another round. Sweeps go in the table's row order, as solve_pgs's over W. Where A would
// hold more rows than T has entries per column (an update on W_AA then costs more than one
// on T), or fewer than 4 sweeps are left after the first 4, the sweeps go on over every row.
// It stops on the same test as solve_pgs, over every row: each row's natural residual times
// its weight at most `tolerance`. Rows outside A have lambda 0 throughout, so the two solve
// the same LCP; only the path differs.
#include <vector>

#include "engine/constraints/delassus.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "engine/core/scratch_matrix.hpp"

namespace sinew {

// The bounds and multipliers of a subset of a RowTable's rows, as solve_pgs reads them
// (friction rows' normal_row re-indexed into the subset).
struct PgsRows {
  std::vector<double> lo, hi, mu, lambda;
  std::vector<int> normal_row;
  int size() const { return static_cast<int>(lo.size()); }
};

class ActiveSetPgs {
 public:
  // As solve_pgs(W, c, weight, rows, ...); W factored (W.dense() false), built for rows.
  // Iterations count every sweep (over every row, then over A in each round) within
  // max_iterations.
  PgsResult solve(Delassus& W, const Eigen::Ref<const VecX>& c, const Eigen::Ref<const VecX>& weight,
                  RowTable& rows, int max_iterations, double tolerance, int subspace_interval);
  // Rows in A at the end of the last solve, whether row i was among them, and the rounds on
  // A it took (0: it ended on T) (tests, diagnostics).
  int active_rows() const { return static_cast<int>(m_active.size()); }
  bool in_active(int i) const { return i < static_cast<int>(m_position.size()) && m_position[i] >= 0; }
  int rounds() const { return m_rounds; }
  // W_AA's stored entry for rows i and j of A (tests): W_ij as entry() forms it for the row
  // that joined A first, or W_ii.
  bool joined_before(int i, int j) const { return m_position[i] < m_position[j]; }
  double formed_entry(int i, int j) {
    return m_block.data()[static_cast<std::size_t>(m_position[j]) * m_stride + m_position[i]];
  }

  // W_AA as a solve_pgs operator over A's positions p (the rows' order), whose entries sit in
  // W_AA's slot slot[p] (the order they joined in): dense, column-major with leading
  // dimension `stride`. w (W_AA lambda + c) and product (multiply_rows' scratch) are
  // `size` values each, w by slot.
  class Block {
   public:
    Block(const double* W, int size, int stride, const int* slot, double* w, double* product)
        : m_W(W), m_size(size), m_stride(stride), m_slot(slot), m_w(w), m_product(product) {}
    double diagonal(int p) const { return column(p)[m_slot[p]]; }
    void start(const Eigen::Ref<const VecX>& lambda, const Eigen::Ref<const VecX>& c);
    double w(int p) const { return m_w[m_slot[p]]; }
    // W_pq as changed(q, .) adds it to w(p).
    double entry(int p, int q) const { return column(q)[m_slot[p]]; }
    void changed(int p, double delta);
    void changed4(const int* p, const double* delta);  // changed(p[k], delta[k]) for k = 0..3
    void multiply_rows(const std::vector<int>& rows, const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> out) const;

   private:
    const double* column(int p) const { return m_W + static_cast<std::size_t>(m_slot[p]) * m_stride; }
    const double* m_W;
    int m_size, m_stride;
    const int* m_slot;
    double* m_w;
    double* m_product;
  };

 private:
  // Adds row i to A (unless there), with its contact's normal and friction rows.
  void add(const RowTable& rows, int i);
  void add_one(int i);
  // W_AA's entries for the rows added since the last call (columns first built).
  void extend_block(const Delassus& W, int rows);

  std::vector<int> m_active;    // A's rows, in the order they joined
  std::vector<int> m_position;  // per row: its position in A, or -1
  std::vector<int> m_friction_begin, m_friction_rows, m_friction_cursor;  // per normal row: its friction rows
  std::vector<int> m_outside_violated;
  std::vector<int> m_order, m_slot, m_sorted;  // A by row; per position its slot; per row its position
  int m_formed = 0;  // rows of A whose entries W_AA holds
  int m_stride = 0;  // W_AA's leading dimension
  int m_rounds = 0;
  PgsRows m_reduced;
  ScratchMatrix m_block, m_vectors;
  ScratchMatrix m_transposed;  // A's columns of T, transposed (extend_block)
  std::vector<const double*> m_new_columns;  // extend_block: per slot, its column of T
};

}  // namespace sinew
