#include "engine/realtime/worker_warmup.hpp"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <thread>

namespace sinew {

void WorkerWarmup::start() {
  // The arena's concurrency ignores a tbb::global_control limit (sinew --threads): both bound it.
  const int threads = std::min<int>(tbb::this_task_arena::max_concurrency(),
                                    tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  const int workers = threads - 1;
  for (int i = 0; i < workers; ++i) {
    ++m_started;
    m_group.run([this] {
      while (!m_go.load(std::memory_order_acquire)) std::this_thread::yield();
      ++m_finished;
    });
  }
}

void WorkerWarmup::wait() {
  release();
  m_group.wait();
}

void keep_threads_awake_until(std::chrono::steady_clock::time_point until) {
  WorkerWarmup warmup;
  warmup.start();
  while (std::chrono::steady_clock::now() < until) std::this_thread::yield();
}

}  // namespace sinew
