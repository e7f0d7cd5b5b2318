#include "engine/core/cpu_placement.hpp"

#include <pthread.h>
#include <sched.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <stdexcept>

namespace sinew {
namespace {

// Empty when the system cannot say (more CPUs than cpu_set_t holds): then nothing is probed.
cpu_set_t current_set() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (pthread_getaffinity_np(pthread_self(), sizeof set, &set) != 0) CPU_ZERO(&set);
  return set;
}

bool set_current(const cpu_set_t& set) { return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0; }

cpu_set_t single(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return set;
}

std::vector<int> cpus_in(const cpu_set_t& set) {
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

volatile double g_probe_sink = 0;

// The probe: what a step does most, small dense products and updates scattered over a few
// hundred kB; ~2-3 ms on the machines above. Its result feeds a volatile sink so that none of
// it is optimised away.
double probe_kernel_ms() {
  const auto start = std::chrono::steady_clock::now();
  Eigen::Matrix<double, 24, 24> K;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j) K(i, j) = 1.0 / (1 + i + j);
  Eigen::Matrix<double, 24, 1> x = Eigen::Matrix<double, 24, 1>::LinSpaced(0, 1);
  double sink = 0;
  for (int it = 0; it < 6000; ++it) {
    x = K * x;
    x /= x.norm();
    sink += x[3];
  }
  constexpr int kSize = 1 << 16;
  static thread_local std::vector<int> index;
  static thread_local std::vector<double> values;
  index.resize(kSize);
  values.assign(kSize, 1.0);
  for (int i = 0; i < kSize; ++i) index[i] = (i * 7919) & (kSize - 1);
  for (int pass = 0; pass < 20; ++pass)
    for (int i = 0; i < kSize; ++i) values[index[i]] = 0.999 * values[index[i]] + 0.001 * values[i];
  sink += values[5];
  g_probe_sink = sink;
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// TBB's workers take `set` at their first entry into the main thread's arena after each
// change (a generation per change: one syscall per worker and change, not per entry).
class WorkerCpus : public tbb::task_scheduler_observer {
 public:
  void assign(const cpu_set_t& set) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_set = set;
    m_generation.fetch_add(1, std::memory_order_release);
  }
  void on_scheduler_entry(bool is_worker) override {
    if (!is_worker) return;
    thread_local long seen = 0;
    const long generation = m_generation.load(std::memory_order_acquire);
    if (seen == generation) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    set_current(m_set);
    seen = generation;
  }

 private:
  std::mutex m_mutex;
  cpu_set_t m_set{};
  std::atomic<long> m_generation{0};
};

// Placement state: the calling thread's set before it was pinned, and the workers' observer.
// The observer lives to the end of the process (never destroyed: TBB may be torn down first).
struct Placement {
  bool pinned = false;
  cpu_set_t before{};
  WorkerCpus* workers = nullptr;
};
Placement& placement() {
  static Placement p;
  return p;
}

}  // namespace

std::vector<int> allowed_cpus() { return cpus_in(current_set()); }

int choose_fastest_cpu(const std::vector<CpuTiming>& timings, double margin) {
  if (timings.size() < 2) return -1;
  const auto [fastest, slowest] = std::minmax_element(
      timings.begin(), timings.end(), [](const CpuTiming& a, const CpuTiming& b) { return a.ms < b.ms; });
  return fastest->ms < (1 - margin) * slowest->ms ? fastest->cpu : -1;
}

std::vector<CpuTiming> probe_cpu_timings() {
  const cpu_set_t before = current_set();
  const std::vector<int> cpus = cpus_in(before);
  std::vector<CpuTiming> timings;
  if (cpus.size() < 2 || static_cast<int>(cpus.size()) > kMaxProbedCpus) return timings;
  for (int cpu : cpus) {
    if (!set_current(single(cpu))) continue;  // taken offline meanwhile: left out
    probe_kernel_ms();  // warm: the page faults and caches of the first run
    // The median of three: a slow vCPU is slow throughout (another guest's load on its host
    // core), not in bursts a best-of would skip, and the median is robust to one interrupt.
    std::array<double, 3> runs{};
    for (double& ms : runs) ms = probe_kernel_ms();
    std::sort(runs.begin(), runs.end());
    timings.push_back({cpu, runs[1]});
  }
  set_current(before);
  return timings;
}

CpuPlacement place_main_thread(const std::string& mode) {
  if (mode != "fastest" && mode != "none")
    throw std::invalid_argument("cpu placement: expected \"fastest\" or \"none\", got \"" + mode + "\"");
  CpuPlacement result;
  release_main_thread();  // probe from the full set
  result.timings = probe_cpu_timings();
  std::string probes;
  for (const CpuTiming& t : result.timings) {
    char text[48];
    std::snprintf(text, sizeof text, "%sCPU %d %.2f ms", probes.empty() ? "" : ", ", t.cpu, t.ms);
    probes += text;
  }
  if (mode == "none") {
    result.summary = "main thread left to the scheduler (" + (probes.empty() ? std::string("not probed") : probes) + ")";
    return result;
  }
  const int cpu = choose_fastest_cpu(result.timings);
  if (cpu < 0) {
    result.summary = result.timings.empty() ? "main thread left to the scheduler (one CPU, or more than " +
                                                  std::to_string(kMaxProbedCpus) + ": not probed)"
                                            : "main thread left to the scheduler (CPUs alike within 10 %: " + probes + ")";
    return result;
  }
  if (!pin_main_thread(cpu)) {
    result.summary = "main thread left to the scheduler (pinning to CPU " + std::to_string(cpu) + " failed)";
    return result;
  }
  result.pinned_cpu = cpu;
  result.summary = "main thread pinned to CPU " + std::to_string(cpu) + ", the fastest (" + probes +
                   "); worker threads on the others";
  return result;
}

bool pin_main_thread(int cpu) {
  release_main_thread();
  Placement& p = placement();
  const cpu_set_t before = current_set();
  if (cpu < 0 || cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, &before)) return false;
  // TBB sizes the calling thread's arena from its CPU set when it first uses it: pinned first,
  // the arena would have one slot and the workers none. A first parallel loop now, on the full
  // set, makes the arena (and the workers, which then start on that set too).
  tbb::parallel_for(0, 4 * tbb::this_task_arena::max_concurrency(), [](int) {});
  if (!set_current(single(cpu))) return false;
  p.pinned = true;
  p.before = before;
  cpu_set_t others = before;
  CPU_CLR(cpu, &others);
  if (!p.workers) p.workers = new WorkerCpus;
  p.workers->assign(CPU_COUNT(&others) > 0 ? others : before);
  p.workers->observe(true);  // no-op when already observing
  return true;
}

void release_main_thread() {
  Placement& p = placement();
  if (!p.pinned) return;
  set_current(p.before);
  if (p.workers) p.workers->assign(p.before);
  p.pinned = false;
}

}  // namespace sinew
