#pragma once
// The order in which element loops that scatter into shared nodes run in parallel: the
// hyperelastic assembly (solve_newton) and the system matrix (assemble_system_matrix).
// Stage 1's sums into vectors go by node instead (node_elements.hpp).
//
// Elements are cut into blocks, runs of consecutive indices within one body, and the blocks
// are coloured so that no two blocks of a colour share a node. A colour's blocks run in
// parallel; each block's elements run in index order on one thread. Every node and matrix
// entry then receives its contributions in a fixed order (colour, then element index),
// whatever the thread count, so sums are bit-identical on 1 and 2 threads; and each thread
// reads per-element data (node lists, reference gradients, scatter maps) in
// memory order. Colouring single elements instead scattered those reads: the bunny_5
// Hessian assembly took 14 ms in colour order against 9 in index order on one thread.
// for_each_scheduled_element.hpp runs the loop.
#include <array>
#include <utility>
#include <vector>

namespace sinew {

struct ElementBlock {
  int first = 0;  // element indices [first, last)
  int last = 0;
};

struct ElementSchedule {
  std::vector<std::vector<ElementBlock>> colors;  // blocks of a colour share no node
};

// Blocks of `block_size` elements (0: elements_per_block(count), see the .cpp) within each
// body range [first, last) of `bodies`, coloured greedily in index order (each block takes the lowest colour free at
// all its nodes). Throws std::runtime_error if a node would need more than 256 colours.
ElementSchedule schedule_elements(const std::vector<std::array<int, 8>>& element_nodes, int num_nodes,
                                  const std::vector<std::pair<int, int>>& bodies, int block_size = 0);

}  // namespace sinew
