#pragma once
// y += a x over n doubles, each entry as one multiply then one add (never a fused
// multiply-add), so that the bits are the same whichever path runs: 4 lanes where the CPU
// has AVX2 (engine/core/cpu_features.hpp), else Eigen's 2 (SSE2, the build's baseline).
// PGS's column updates (delassus.hpp) spend most of their time here, in loads and stores.
namespace sinew {

void add_scaled(double* y, const double* x, double a, int n);

// add_scaled(y, x[k], a[k], n) for k = 0..3 in turn, in one pass over y (the same bits:
// y's entries see the same adds in the same order): PGS's products T lambda (delassus.cpp).
void add_scaled4(double* y, const double* const* x, const double* a, int n);

// y += column(i) a[i] over i < count with a[i] != 0, in i's order, four columns a pass: the
// bits of add_scaled on each in turn.
template <typename Column>
void add_scaled_nonzero(double* y, int n, int count, const double* a, Column column) {
  const double* held_columns[4];
  double held_scales[4];
  int held = 0;
  for (int i = 0; i < count; ++i) {
    if (a[i] == 0) continue;
    held_columns[held] = column(i), held_scales[held] = a[i];
    if (++held == 4) add_scaled4(y, held_columns, held_scales, n), held = 0;
  }
  for (int k = 0; k < held; ++k) add_scaled(y, held_columns[k], held_scales[k], n);
}

// y += (x0 a0 + x1 a1) + x2 a2 over n doubles, in that order, each product rounded on its
// own: the bits of Eigen's `y += x0 * a0 + x1 * a1 + x2 * a2` on the build's baseline.
// Delassus columns (T = G J^T, one node's three columns of G per stencil entry).
void add_scaled3(double* y, const double* x0, const double* x1, const double* x2, double a0, double a1, double a2,
                 int n);
// y = (x0 a0 + x1 a1) + x2 a2: the bits of add_scaled3 on y = 0, but for the sign of a zero
// sum (-0 here), and without reading or zeroing y first.
void set_scaled3(double* y, const double* x0, const double* x1, const double* x2, double a0, double a1, double a2,
                 int n);

}  // namespace sinew
