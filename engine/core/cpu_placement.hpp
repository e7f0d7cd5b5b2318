#pragma once
// Where the calling (main) thread runs, and how fast each CPU is now. Virtual machines may give
// a process CPUs of unequal speed that the scheduler cannot see: on the 2-vCPU Firecracker
// machines sinew is measured on, one vCPU ran a fixed kernel 1.5x slower than the other for
// tens of minutes (24.9 against 16.4 ms, eight alternating runs pinned to each; the same run
// concurrently, so not one shared core), then as fast, then slower again within seconds
// (another guest's load on its host core, presumably). sinew_bench's finger324 took 1.00
// against 0.64 ms a step on one thread pinned to either. Unpinned, the main thread, which runs
// the step's serial stages (SQP, PGS), lands on either: the 30-45 % "drift" of earlier
// sessions' figures. sinew_bench records each CPU's probe time with every scene, so that a
// figure can be read with the machine's state, and can pin the main thread to the fastest
// CPU: in two alternating passes while one vCPU was 1.45x slower, finger324flat 3.08 / 3.00
// -> 2.65 / 2.68 ms, creature365 2.14 / 2.05 -> 2.02 / 2.12 (bench/results/README.md,
// "session 55"). Not by default: which CPU is faster changes within seconds to minutes, and a
// pinned thread cannot follow. Placement changes speed only: results do not depend on it (nor
// on the thread count).
#include <string>
#include <vector>

namespace sinew {

struct CpuTiming {
  int cpu = -1;     // the CPU's number (as sched_setaffinity counts them)
  double ms = 0;    // the probe kernel's median time there, of three runs
};

struct CpuPlacement {
  std::vector<CpuTiming> timings;  // per CPU the thread may run on (empty: not probed)
  int pinned_cpu = -1;             // the CPU the main thread was pinned to (-1: left free)
  std::string summary;             // one line for a run's report: what was done and why
};

// The CPU to pin to: the fastest, when its time is below (1 - margin) of the slowest's;
// otherwise -1 (CPUs alike within the margin, or fewer than two).
int choose_fastest_cpu(const std::vector<CpuTiming>& timings, double margin = 0.1);

// Times the probe kernel (dense 24 x 24 products and scattered updates, ~2-3 ms; the median of
// three runs after a warm one) on each CPU the calling thread may run on, pinning it to each
// in turn; restores its CPU set after.
// At most kMaxProbedCpus CPUs (more: none probed, returns empty).
constexpr int kMaxProbedCpus = 16;
std::vector<CpuTiming> probe_cpu_timings();

// Probes (probe_cpu_timings) and, with mode "fastest", pins the calling thread to choose_fastest_cpu's CPU, if any, and
// have TBB's worker threads, from their next entry into the calling thread's arena on, run on
// the CPUs it was allowed but that one; mode "none" pins nothing. Either way the summary line
// quotes the probe times. Throws std::invalid_argument for another mode.
CpuPlacement place_main_thread(const std::string& mode);

// Pins the calling thread to `cpu` (one it may run on now) and TBB's workers, from their next
// entry into its arena on, to the others it may run on (all of them if none is left); false,
// with nothing changed, if `cpu` is not among them or the system refuses.
bool pin_main_thread(int cpu);

// A worker busy in the arena when the set changes keeps its old set until it next enters.
// place_main_thread, pin_main_thread and release_main_thread: from the main thread only.

// Undoes place_main_thread or pin_main_thread: the calling thread and the workers (at their next entry) back on
// the CPU set the calling thread had before it.
void release_main_thread();

// The CPUs the calling thread may run on now.
std::vector<int> allowed_cpus();

}  // namespace sinew
