#pragma once
// Projected Gauss-Seidel for the boxed LCP of paper 000, eq. 23 (after [CPS92]):
//   find lambda with lo <= lambda <= hi and w = W lambda + c such that
//   lambda_i = lo_i => w_i >= 0,  lambda_i = hi_i => w_i <= 0,  otherwise w_i = 0.
// Friction rows take lo = -mu lambda_n, hi = +mu lambda_n from their normal row, updated
// as the sweep goes (a box approximation of the Coulomb cone, two rows per contact).
#include "engine/constraints/row_table.hpp"

namespace sinew {

struct PgsResult {
  int iterations = 0;
  double change = 0;  // largest |delta lambda| of the last sweep, relative to max |lambda|
};

// W: dense rows x rows, symmetric positive semi-definite with a positive diagonal.
// Starts from rows.lambda (warm start), clamped into the bounds; writes it back.
PgsResult solve_pgs(const MatX& W, const VecX& c, RowTable& rows, int max_iterations, double tolerance);

// Largest violation of the LCP conditions at lambda (0 at an exact solution), in the
// units of w; for tests and diagnostics.
double lcp_residual(const MatX& W, const VecX& c, const RowTable& rows);

}  // namespace sinew
