#pragma once
// Central differences over an element's node coordinates, for the element tests: the first
// 3 * nodes.count coordinates are perturbed, the rest of the result stays zero.
#include "engine/assembly/element_kernels.hpp"

namespace sinew::test {

// d energy / dx, with energy(ElementNodes) -> double.
template <typename Energy>
Vec24 fd_gradient(const ElementNodes& nodes, double eps, Energy energy) {
  Vec24 fd = Vec24::Zero();
  for (int i = 0; i < 3 * nodes.count; ++i) {
    ElementNodes plus = nodes, minus = nodes;
    plus.x[i / 3][i % 3] += eps;
    minus.x[i / 3][i % 3] -= eps;
    fd[i] = (energy(plus) - energy(minus)) / (2 * eps);
  }
  return fd;
}

// d gradient / dx (column i: the derivative along coordinate i), with gradient(ElementNodes) -> Vec24.
template <typename Gradient>
Mat24 fd_jacobian(const ElementNodes& nodes, double eps, Gradient gradient) {
  Mat24 fd = Mat24::Zero();
  for (int i = 0; i < 3 * nodes.count; ++i) {
    ElementNodes plus = nodes, minus = nodes;
    plus.x[i / 3][i % 3] += eps;
    minus.x[i / 3][i % 3] -= eps;
    fd.col(i) = (gradient(plus) - gradient(minus)) / (2 * eps);
  }
  return fd;
}

}  // namespace sinew::test
