#include "engine/core/cpu_placement.hpp"

#include <doctest/doctest.h>
#include <pthread.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace sinew;

TEST_CASE("choose_fastest_cpu: the fastest only when it beats the slowest by more than the margin") {
  CHECK(choose_fastest_cpu({}) == -1);
  CHECK(choose_fastest_cpu({{3, 1.0}}) == -1);                  // one CPU: nothing to choose
  CHECK(choose_fastest_cpu({{0, 1.00}, {1, 1.05}}) == -1);      // alike within 10 %
  CHECK(choose_fastest_cpu({{0, 0.95}, {1, 1.05}}) == -1);      // 0.95 > 0.9 * 1.05
  CHECK(choose_fastest_cpu({{0, 2.5}, {1, 1.6}}) == 1);         // the measured 1.5x
  CHECK(choose_fastest_cpu({{4, 1.0}, {6, 2.0}, {7, 1.5}}) == 4);
  CHECK(choose_fastest_cpu({{0, 1.0}, {1, 1.5}}, 0.5) == -1);   // a wider margin
}

TEST_CASE("probe_cpu_timings: one positive time per allowed CPU, the CPU set restored") {
  const std::vector<int> before = allowed_cpus();
  REQUIRE(!before.empty());
  const std::vector<CpuTiming> timings = probe_cpu_timings();
  CHECK(allowed_cpus() == before);
  if (before.size() < 2 || static_cast<int>(before.size()) > kMaxProbedCpus) {
    CHECK(timings.empty());
    return;
  }
  REQUIRE(timings.size() == before.size());
  for (std::size_t k = 0; k < timings.size(); ++k) {
    CHECK(timings[k].cpu == before[k]);
    CHECK(timings[k].ms > 0);
  }
}

TEST_CASE("pin_main_thread: the main thread on its CPU, no worker on that CPU alone, released after") {
  const std::vector<int> before = allowed_cpus();
  REQUIRE(!before.empty());
  CHECK_FALSE(pin_main_thread(-1));
  CHECK_FALSE(pin_main_thread(1 << 20));
  CHECK(allowed_cpus() == before);
  const int cpu = before.back();
  REQUIRE(pin_main_thread(cpu));
  CHECK(allowed_cpus() == std::vector<int>{cpu});
  // The workers on the others: a worker takes the set at its next entry into the arena (one
  // still in it from an earlier loop keeps its old one), so each round first lets them
  // leave. oneTBB starts its workers on the process's set, whoever starts them: without the
  // observer they would stay on every CPU, the main's included.
  std::vector<int> others;
  for (int c : before)
    if (c != cpu) others.push_back(c);
  std::mutex mutex;
  std::vector<std::vector<int>> worker_sets;
  const std::thread::id main_id = std::this_thread::get_id();
  for (int round = 0; round < 5 && worker_sets.empty() && !others.empty(); ++round) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    tbb::parallel_for(0, 64, [&](int) {
      volatile double sum = 0;
      for (int k = 0; k < 200000; ++k) sum = sum + k;
      if (std::this_thread::get_id() == main_id) return;
      std::lock_guard<std::mutex> lock(mutex);
      worker_sets.push_back(allowed_cpus());
    });
  }
  if (!others.empty() && tbb::this_task_arena::max_concurrency() > 1) CHECK(!worker_sets.empty());
  for (const std::vector<int>& set : worker_sets) CHECK(set == others);
  release_main_thread();
  CHECK(allowed_cpus() == before);
  release_main_thread();  // twice: nothing more
  CHECK(allowed_cpus() == before);
}

TEST_CASE("place_main_thread: none pins nothing and quotes the probe; another mode is an error") {
  const std::vector<int> before = allowed_cpus();
  const CpuPlacement none = place_main_thread("none");
  CHECK(none.pinned_cpu == -1);
  CHECK(allowed_cpus() == before);
  CHECK(none.summary.find("left to the scheduler") != std::string::npos);
  CHECK_THROWS_AS(place_main_thread("fast"), std::invalid_argument);
  const CpuPlacement fastest = place_main_thread("fastest");
  if (fastest.pinned_cpu >= 0) {
    CHECK(fastest.pinned_cpu == choose_fastest_cpu(fastest.timings));
    CHECK(allowed_cpus() == std::vector<int>{fastest.pinned_cpu});
  } else {
    CHECK(allowed_cpus() == before);
  }
  release_main_thread();
  CHECK(allowed_cpus() == before);
}
