#pragma once
// Keeps oneTBB's worker threads awake through the end of a pacing wait. A worker idle for a
// frame period sleeps, and on this project's 2-core VM it took 1.4 ms on average to join a
// parallel loop after 20 ms idle (0.1 ms after 1 ms): the paced creature's steps ran on one
// thread for most of their first millisecond (median step 2.19 ms as fast as possible, 3.00
// ms paced; stage 1 0.15 -> 0.27 ms). Started shortly before the frame's slot, one task per
// worker spins until released at the slot, so the step finds the workers running: started 4
// ms ahead, the paced creature's median step was 2.30-2.47 ms and stage 1 0.156-0.158 ms, as
// unpaced (2 ms ahead: 2.63-2.93 and 0.19-0.20 ms). The price: every thread spins for the
// last 4 ms of each wait (a quarter of the cores' time at 60 Hz).
#include <atomic>
#include <chrono>

#include <tbb/task_group.h>

namespace sinew {

class WorkerWarmup {
 public:
  // One spinning task per worker thread allowed (none with one thread).
  void start();
  // Ends the spinning tasks (the step begins).
  void release() { m_go.store(true, std::memory_order_release); }
  // Tasks started and finished (tests).
  int started() const { return m_started; }
  int finished() const { return m_finished.load(); }
  // Releases and waits for the tasks: a task no worker picked up runs here and returns at once.
  void wait();
  ~WorkerWarmup() { wait(); }

 private:
  std::atomic<bool> m_go{false};
  std::atomic<int> m_finished{0};
  int m_started = 0;
  tbb::task_group m_group;
};

// Keeps every thread awake until `until`: the workers in a WorkerWarmup's tasks, this one
// spinning; returns with the tasks ended.
void keep_threads_awake_until(std::chrono::steady_clock::time_point until);

}  // namespace sinew
