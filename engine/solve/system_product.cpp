#include "engine/solve/system_product.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sinew {

void multiply_system(const SparseMatrix& A, const Eigen::Ref<const VecX>& x, VecX& out) {
  out.resize(A.rows());
  if (!A.isCompressed()) {  // assembled systems are; kept correct for any other
    out.noalias() = A * x;
    return;
  }
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  const double* in = x.data();
  const auto columns = [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      double sum = 0;
      for (int k = outer[j]; k < outer[j + 1]; ++k) sum += value[k] * in[inner[k]];
      out[j] = sum;
    }
  };
  // Below about 64k entries (the finger's 360 DOFs: 40k) a task costs more than it saves.
  constexpr long kParallelEntries = 1 << 16;
  if (A.nonZeros() < kParallelEntries) {
    columns(0, static_cast<int>(A.cols()));
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(A.cols()), 256),
                    [&](const tbb::blocked_range<int>& r) { columns(r.begin(), r.end()); });
}

void multiply_diagonal(const VecX& d, const VecX& x, VecX& out) {
  out.resize(x.size());
  out.array() = d.array() * x.array() + 0.0;
}

}  // namespace sinew
