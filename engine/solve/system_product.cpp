#include "engine/solve/system_product.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <stdexcept>

namespace sinew {

namespace {

// Below about 64k entries (the finger's 360 DOFs: 40k) a task costs more than it saves.
constexpr long kParallelEntries = 1 << 16;

}  // namespace

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
  if (A.nonZeros() < kParallelEntries) {
    columns(0, static_cast<int>(A.cols()));
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(A.cols()), 256),
                    [&](const tbb::blocked_range<int>& r) { columns(r.begin(), r.end()); });
}

void multiply_node_blocked(const SparseMatrix& A, const Eigen::Ref<const VecX>& x, VecX& out) {
  const int* outer = A.outerIndexPtr();
  const int nodes = static_cast<int>(A.cols() / 3);
  bool blocked = A.isCompressed() && A.cols() % 3 == 0 && A.rows() == A.cols();
  for (int j = 0; blocked && j < nodes; ++j) {
    const int length = outer[3 * j + 1] - outer[3 * j];
    blocked = length % 3 == 0 && outer[3 * j + 2] - outer[3 * j + 1] == length &&
              outer[3 * j + 3] - outer[3 * j + 2] == length;
  }
  const auto refuse = [] {
    throw std::invalid_argument("multiply_node_blocked: the matrix does not have the system pattern's node blocks");
  };
  if (!blocked) refuse();
  assert(has_node_blocks(A));  // checked in the sanitizer build
  out.resize(A.rows());
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  const double* in = x.data();
  const unsigned last_node_row = static_cast<unsigned>(A.rows()) - 3;
  const auto node_columns = [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      const int first = outer[3 * j], length = outer[3 * j + 1] - first;
      const int* rows = inner + first;
      const double* v0 = value + first;
      const double* v1 = value + outer[3 * j + 1];
      const double* v2 = value + outer[3 * j + 2];
      double s0 = 0, s1 = 0, s2 = 0;
      for (int k = 0; k < length; k += 3) {
        // A node's first row within [0, n - 3]: no read past x (the alignment of the rows and
        // the other columns' rows are has_node_blocks's to check).
        if (static_cast<unsigned>(rows[k]) > last_node_row) refuse();
        const double* xi = in + rows[k];
        s0 += v0[k] * xi[0];
        s0 += v0[k + 1] * xi[1];
        s0 += v0[k + 2] * xi[2];
        s1 += v1[k] * xi[0];
        s1 += v1[k + 1] * xi[1];
        s1 += v1[k + 2] * xi[2];
        s2 += v2[k] * xi[0];
        s2 += v2[k + 1] * xi[1];
        s2 += v2[k + 2] * xi[2];
      }
      out[3 * j] = s0, out[3 * j + 1] = s1, out[3 * j + 2] = s2;
    }
  };
  if (A.nonZeros() < kParallelEntries) {
    node_columns(0, nodes);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, nodes, 96),
                    [&](const tbb::blocked_range<int>& r) { node_columns(r.begin(), r.end()); });
}

bool has_node_blocks(const SparseMatrix& A) {
  if (!A.isCompressed() || A.cols() % 3 != 0 || A.rows() != A.cols()) return false;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (int j = 0; j < A.cols() / 3; ++j) {
    const int first = outer[3 * j], length = outer[3 * j + 1] - first;
    if (length % 3 != 0) return false;
    for (int d = 1; d < 3; ++d)
      if (outer[3 * j + d + 1] - outer[3 * j + d] != length ||
          !std::equal(inner + first, inner + first + length, inner + outer[3 * j + d]))
        return false;
    for (int k = 0; k < length; k += 3)
      if (inner[first + k] % 3 != 0 || inner[first + k + 1] != inner[first + k] + 1 ||
          inner[first + k + 2] != inner[first + k] + 2)
        return false;
  }
  return true;
}

void multiply_diagonal(const VecX& d, const VecX& x, VecX& out) {
  out.resize(x.size());
  out.array() = d.array() * x.array() + 0.0;
}

}  // namespace sinew
