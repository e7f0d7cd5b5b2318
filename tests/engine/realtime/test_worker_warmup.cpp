// WorkerWarmup (engine/realtime/worker_warmup.hpp): one task per worker thread, which spins
// until released, never finishes before that, and is always waited for (one thread: none).
#include <doctest/doctest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "engine/realtime/worker_warmup.hpp"

using namespace sinew;

TEST_CASE("worker warmup: a spinning task per worker, ended by release, waited for") {
  for (const int threads : {1, 2}) {
    CAPTURE(threads);
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    WorkerWarmup warmup;
    warmup.start();
    // A worker per thread allowed beyond this one, as the machine has them.
    CHECK(warmup.started() == std::min(threads, tbb::this_task_arena::max_concurrency()) - 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(warmup.finished() == 0);  // spinning, or not picked up yet: never done before release
    warmup.release();
    warmup.wait();  // a task a worker holds ends; one no worker picked up runs here
    CHECK(warmup.finished() == warmup.started());
  }
}
