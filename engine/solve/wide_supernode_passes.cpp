#include "engine/solve/wide_supernode_passes.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cassert>
#include <thread>

namespace sinew {

namespace {

// Until the other thread has finished a task (release there, acquire here): a pause per
// spin, then yields, as on a loaded machine the other thread may be descheduled.
void wait_until_done(const std::atomic<int>& flag) {
  for (int spins = 0; !flag.load(std::memory_order_acquire);) {
    if (spins < 64) {
      ++spins;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    } else {
      std::this_thread::yield();
    }
  }
}

}  // namespace

void WideSupernodePasses::reserve(int columns) {
  const int tasks = 3 * ((columns + kTreeBlock - 1) / kTreeBlock);
  if (!m_progress || static_cast<int>(m_progress->done.size()) < tasks) m_progress = std::make_unique<Progress>(tasks);
}

template <class Task>
void WideSupernodePasses::run_in_claim_order(int tasks, Task run) {
  assert(m_progress && static_cast<int>(m_progress->done.size()) >= tasks);  // reserve() first
  Progress& progress = *m_progress;
  progress.threads.store(0, std::memory_order_relaxed);
  for (int t = 0; t < tasks; ++t) progress.done[t].store(0, std::memory_order_relaxed);
  progress.next_task.store(0, std::memory_order_relaxed);
  const auto work = [&] {
    bool ran = false;
    for (int task; (task = progress.next_task.fetch_add(1, std::memory_order_relaxed)) < tasks; ran = true) {
      run(task);
      progress.done[task].store(1, std::memory_order_release);
    }
    if (ran) progress.threads.fetch_add(1, std::memory_order_relaxed);
  };
  tbb::parallel_invoke(work, work);
}

template <class Real>
void WideSupernodePasses::forward(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  if (!worth_two_threads(s.columns)) return tree_forward(s, y, gather);
  double* ys = y + s.first;
  const int columns = s.columns, below = s.height - s.columns, blocks = (columns + kTreeBlock - 1) / kTreeBlock;
  const auto block_end = [&](int J) { return std::min(columns, (J + 1) * kTreeBlock); };
  // The rows after block J (the triangle's, then those below it), in two halves.
  const auto middle = [&](int J) { return block_end(J) + (s.height - block_end(J)) / 2; };
  // Rows r0..r1-1 of the supernode take columns c0..c1-1.
  const auto update = [&](int c0, int c1, int r0, int r1) {
    if (r0 < columns) tree_forward_rect(s, ys, c0, c1, r0, std::min(r1, columns), ys + r0);
    if (r0 = std::max(r0, columns); r1 > r0) tree_forward_rect(s, ys, c0, c1, r0, r1, gather + (r0 - columns));
  };
  for (int i = 0; i < below; ++i) gather[i] = y[s.rows[columns + i]];
  const auto done = [&](int J, int kind) -> const std::atomic<int>& { return m_progress->done[3 * J + kind]; };
  run_in_claim_order(3 * blocks, [&](int task) {
    const int J = task / 3, kind = task % 3, b0 = J * kTreeBlock, b1 = block_end(J);
    if (kind == 0) {  // block J's triangle, once its rows took every column before it
      if (J > 0) {
        wait_until_done(done(J - 1, 1));
        if (middle(J - 1) < b1) wait_until_done(done(J - 1, 2));
      }
      tree_forward_diagonal(s, ys, b0, b1);
    } else {  // a half of the rows after block J take its columns, after the columns before
      wait_until_done(done(J, 0));
      if (J > 0) wait_until_done(done(J - 1, 1)), wait_until_done(done(J - 1, 2));
      if (kind == 1) update(b0, b1, b1, middle(J));
      else update(b0, b1, middle(J), s.height);
    }
  });
  for (int i = 0; i < below; ++i) y[s.rows[columns + i]] = gather[i];
}

template <class Real>
void WideSupernodePasses::backward(const BasicSupernodeView<Real>& s, double* y, double* gather) {
  if (!worth_two_threads(s.columns)) return tree_backward(s, y, gather);
  double* ys = y + s.first;
  const int columns = s.columns, below = s.height - s.columns, blocks = (columns + kTreeBlock - 1) / kTreeBlock;
  const auto block_end = [&](int J) { return std::min(columns, (J + 1) * kTreeBlock); };
  for (int i = 0; i < below; ++i) gather[i] = y[s.rows[columns + i]];
  // Tasks from the last block back: its two halves of columns, then its triangle.
  const auto done = [&](int J, int kind) -> const std::atomic<int>& { return m_progress->done[3 * (blocks - 1 - J) + kind]; };
  run_in_claim_order(3 * blocks, [&](int task) {
    const int J = blocks - 1 - task / 3, kind = task % 3, b0 = J * kTreeBlock, b1 = block_end(J);
    if (kind < 2) {  // half of block J's columns: dot products with the rows below and after the block
      const int split = b0 + (b1 - b0) / 8 * 4, c0 = kind == 0 ? b0 : split, c1 = kind == 0 ? split : b1;
      if (below > 0) tree_backward_rect(s, gather, columns, s.height, c0, c1, ys);
      if (J + 1 < blocks) {
        wait_until_done(done(J + 1, 2));
        tree_backward_rect(s, ys + b1, b1, columns, c0, c1, ys);
      }
    } else {  // block J's triangle, once both halves are in
      wait_until_done(done(J, 0)), wait_until_done(done(J, 1));
      tree_backward_diagonal(s, ys, b0, b1);
    }
  });
}

template void WideSupernodePasses::forward(const SupernodeView&, double*, double*);
template void WideSupernodePasses::forward(const SingleSupernodeView&, double*, double*);
template void WideSupernodePasses::backward(const SupernodeView&, double*, double*);
template void WideSupernodePasses::backward(const SingleSupernodeView&, double*, double*);

}  // namespace sinew
