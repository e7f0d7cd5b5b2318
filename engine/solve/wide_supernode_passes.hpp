#pragma once
// A wide supernode's passes (tree_kernels.hpp) on two threads, with the bits of one thread.
// The tree solve's split (supernodal_tree_solve.hpp) ends at the top of the elimination
// tree, which a nested-dissection order makes one wide supernode, the last separator:
// cube_20's factor of 2.97 M entries has a 936-column root of 0.88 M, a triangle that one
// thread solved while the other waited (sessions 47-48: ~0.11 ms a pass).
// Blocks of kTreeBlock columns (tree_kernels.hpp), three tasks each, claimed in this order:
//   forward, first block first: the block's triangle (once its rows took every earlier
//     column), then the rows after it (the triangle's, then those below it) take its
//     columns, in two halves of rows;
//   backward, last block first: its columns' dot products with the rows below the triangle
//     and with the triangle's rows after the block (once those are final), in two halves of
//     columns, then the block's triangle.
// Every entry takes the same operations in the same order as in tree_forward / tree_backward,
// whichever thread runs its task. A task waits only for tasks claimed before it, so a thread
// alone runs them all in order, and no task waits for one that no thread holds.
#include <atomic>
#include <memory>
#include <vector>

#include "engine/solve/supernode_view.hpp"
#include "engine/solve/tree_kernels.hpp"

namespace sinew {

class WideSupernodePasses {
 public:
  // Whether a supernode of that many columns is split into tasks: the backward pass's
  // blocks are what lets two threads give one thread's bits.
  static bool worth_two_threads(int columns) { return backward_in_blocks(columns); }
  // Sizes the tasks' flags for supernodes of up to `columns` columns (no allocation after).
  void reserve(int columns);
  // tree_forward / tree_backward on up to two threads (the same y, gather and result); a
  // supernode not worth two threads runs them on this one.
  template <class Real>
  void forward(const BasicSupernodeView<Real>& s, double* y, double* gather);
  template <class Real>
  void backward(const BasicSupernodeView<Real>& s, double* y, double* gather);
  // How many threads ran tasks in the last pass (tests: whether the two threads overlapped).
  int last_pass_threads() const { return m_progress ? m_progress->threads.load(std::memory_order_relaxed) : 0; }

 private:
  struct Progress {  // on the heap: the solver that holds this is moved
    explicit Progress(int tasks) : done(tasks) {}
    std::atomic<int> next_task{0};
    std::atomic<int> threads{0};  // that ran at least one task of the last pass
    std::vector<std::atomic<int>> done;  // per task: 1 once done
  };
  // Tasks 0..tasks-1 by both threads, claimed in order; each marked done after run(task).
  template <class Task>
  void run_in_claim_order(int tasks, Task run);
  std::unique_ptr<Progress> m_progress;
};

}  // namespace sinew
