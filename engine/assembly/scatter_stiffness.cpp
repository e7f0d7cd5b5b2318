#include "engine/assembly/scatter_stiffness.hpp"

#include <tbb/parallel_for.h>

#include "engine/assembly/element_kernels.hpp"

namespace sinew {

namespace {

// K's 3x3 blocks (a, b) over the element's n nodes, at its scatter positions.
template <class Matrix>
void scatter_blocks(const Model& model, int e, const Matrix& K, double coeff, double* values) {
  const int* scatter = model.pattern.element_scatter.data() + model.pattern.scatter_begin[e];
  const int n = element_node_count(model, e);
  for (int ab = 0; ab < n * n; ++ab) {
    if (scatter[3 * ab] < 0) continue;  // a fixed node
    const int a = ab / n, b = ab % n;
    for (int d = 0; d < 3; ++d) {
      double* column = values + scatter[3 * ab + d];
      for (int r = 0; r < 3; ++r) column[r] += coeff * K(3 * a + r, 3 * b + d);
    }
  }
}

}  // namespace

void scatter_element_matrix(const Model& model, int e, const Mat24& K, double coeff, double* values) {
  scatter_blocks(model, e, K, coeff, values);
}

void scatter_element_matrix(const Model& model, int e, const Mat12& K, double coeff, double* values) {
  scatter_blocks(model, e, K, coeff, values);
}

void scatter_warped_stiffness(const Model& model, const std::vector<Mat3>& R,
                              const std::vector<double>& coeff, double* values) {
  for (const std::vector<int>& color : model.element_colors) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, color.size(), 16), [&](const auto& range) {
      Mat24 K;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const int e = color[i];
        if (coeff[e] == 0) continue;
        element_warped_stiffness(model, e, R[e], K);
        scatter_element_matrix(model, e, K, coeff[e], values);
      }
    });
  }
}

}  // namespace sinew
