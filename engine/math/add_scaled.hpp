#pragma once
// y += a x over n doubles, each entry as one multiply then one add (never a fused
// multiply-add), so that the bits are the same whichever path runs: 4 lanes where the CPU
// has AVX2 (engine/core/cpu_features.hpp), else Eigen's 2 (SSE2, the build's baseline).
// PGS's column updates (delassus.hpp) spend most of their time here, in loads and stores.
namespace sinew {

void add_scaled(double* y, const double* x, double a, int n);

}  // namespace sinew
