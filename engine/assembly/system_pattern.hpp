#pragma once
// Sparsity of the global system matrix over free degrees of freedom and the scatter map
// from element blocks into it, built once per topology.
//
// Storage: compressed columns, full (both triangles), with the three rows of a node block
// contiguous in each column, so entry (r, d) of the 3x3 block (a, b) of an element with n
// nodes lands at values[element_scatter[scatter_begin[e] + (n a + b) * 3 + d] + r].
#include <Eigen/SparseCore>
#include <array>
#include <vector>

namespace sinew {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

struct SystemPattern {
  SparseMatrix matrix;  // pattern with zero values; copied into the state's working matrix
  // Per element with n nodes (8 for hex8, 4 for tet4), per local pair (a, b) (a-major), per
  // column d of the block: position in values of row 3*free(a)+0 of column 3*free(b)+d; -1 if
  // a or b is fixed. Element e's 3 n^2 entries start at scatter_begin[e] (a tet's 48 ints
  // instead of a padded 192: the assembly streams them once per element).
  std::vector<int> scatter_begin;  // per element, then the total
  std::vector<int> element_scatter;
  std::vector<int> diagonal;  // per free DOF: position of its diagonal entry
};

// `element_nodes` are global node indices; `free_index` maps nodes to free-node indices.
SystemPattern build_system_pattern(const std::vector<std::array<int, 8>>& element_nodes,
                                   const std::vector<int>& free_index, int num_free);

}  // namespace sinew
