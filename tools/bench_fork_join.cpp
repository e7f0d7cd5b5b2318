// sinew_bench_fork_join: how soon an idle oneTBB worker joins a short parallel loop on this
// machine. A step of a small scene is a chain of 20-200 us loops between serial stages (the
// pressed finger: ~24 a step), so a worker that joins late, or not at all, leaves the loop to
// the calling thread: on the project's 2-core VM the flat-pressed finger ran as fast on one
// thread as on two (bench/results/README.md, session 38).
//
// Each round: the calling thread works alone for a gap (the serial stage before a loop), then
// runs a loop of 64 chunks of 2 us (128 us of work) through tbb::parallel_for. Per gap: the
// median and 90th percentile of the time from the loop's start to the first chunk another
// thread ran (over the rounds where one did), the share of rounds where no other thread ran
// any chunk, and the median loop time against the same work on one thread. For comparison,
// the same rounds with one plain std::thread that spins on an atomic between loops (what a
// worker that never sleeps would give; not how sinew runs). JSON out.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"  // quantile
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kChunks = 64;
constexpr auto kChunkWork = std::chrono::microseconds(2);

void busy(Clock::duration d) {
  const auto until = Clock::now() + d;
  while (Clock::now() < until) {
  }
}

void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

double micro(Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }

// One round's figures: when another thread first ran a chunk (-1: never), the loop's time.
struct Round {
  double join_us = -1, loop_us = 0;
};

// The loop on oneTBB's workers.
Round tbb_round() {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<double> first{-1};
  const auto start = Clock::now();
  tbb::parallel_for(tbb::blocked_range<int>(0, kChunks, 1), [&](const tbb::blocked_range<int>& r) {
    if (std::this_thread::get_id() != caller) {
      double expected = -1;
      first.compare_exchange_strong(expected, micro(Clock::now() - start));
    }
    for (int i = r.begin(); i < r.end(); ++i) busy(kChunkWork);
  });
  return {first.load(), micro(Clock::now() - start)};
}

// The reference: one helper thread that spins between loops and claims chunks by an atomic
// counter; the caller claims too and waits for the last.
class SpinningHelper {
 public:
  SpinningHelper() : m_thread([this] { help(); }) {}
  ~SpinningHelper() {
    m_stop = true;
    m_thread.join();
  }
  Round round() {
    m_first = -1;
    m_done = 0;
    m_start = Clock::now();
    m_next.store(0, std::memory_order_release);  // publishes the round
    run_chunks(false);
    while (m_done.load(std::memory_order_acquire) < kChunks) relax();  // every chunk claimed: m_next >= kChunks
    return {m_first.load(), micro(Clock::now() - m_start)};
  }

 private:
  void run_chunks(bool helper) {
    for (int i; (i = m_next.fetch_add(1, std::memory_order_acq_rel)) < kChunks;) {
      if (helper) {
        double expected = -1;
        m_first.compare_exchange_strong(expected, micro(Clock::now() - m_start));
      }
      busy(kChunkWork);
      m_done.fetch_add(1, std::memory_order_release);
    }
  }
  void help() {
    while (!m_stop) {
      if (m_next.load(std::memory_order_acquire) < kChunks) run_chunks(true);
      else relax();
    }
  }
  std::atomic<int> m_next{kChunks}, m_done{0};
  std::atomic<double> m_first{-1};
  std::atomic<bool> m_stop{false};
  Clock::time_point m_start;
  std::thread m_thread;
};

nlohmann::json summarize(const char* workers, double gap_us, const std::vector<Round>& rounds, double alone_us) {
  std::vector<double> joins, loops;
  int never = 0;
  for (const Round& r : rounds) {
    loops.push_back(r.loop_us);
    if (r.join_us < 0) ++never;
    else joins.push_back(r.join_us);
  }
  const double share_never = static_cast<double>(never) / static_cast<double>(rounds.size());
  // No loop joined: no latency to report (-1), not quantile's 0 of no samples.
  const double join_median = joins.empty() ? -1 : quantile(joins, 0.5), join_p90 = joins.empty() ? -1 : quantile(joins, 0.9);
  const double loop = quantile(loops, 0.5);
  std::printf("  %-9s gap %6.0f us: join median %7.1f us, p90 %7.1f us; no join in %4.1f %% of loops; "
              "loop median %6.1f us (%.2fx one thread)\n",
              workers, gap_us, join_median, join_p90, 100 * share_never, loop, alone_us / loop);
  return {{"workers", workers}, {"gap_us", gap_us}, {"rounds", rounds.size()},
          {"join_median_us", join_median}, {"join_p90_us", join_p90},
          {"share_without_join", share_never}, {"loop_median_us", loop}, {"speedup", alone_us / loop}};
}

}  // namespace

int main(int argc, char** argv) {
  cli::Options options("sinew_bench_fork_join [--rounds N] [--out FILE]",
                       "How soon an idle oneTBB worker joins a short parallel loop (64 chunks of 2 us)\n"
                       "after the calling thread worked alone for 2 us to 1.5 ms, on 2 threads; and the\n"
                       "same with a helper thread that spins between loops, for comparison. Medians.",
                       {{"--rounds", "N", "loops per gap and kind of worker (default 300)"},
                        {"--out", "FILE", "JSON results (default bench_fork_join.json)"}},
                       0);
  int rounds = 300;
  std::string out;
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    rounds = options.get_int("--rounds", 300, 10);
    out = options.get("--out", "bench_fork_join.json");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_bench_fork_join: %s\n", e.what());
    return 2;
  }
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  if (std::thread::hardware_concurrency() < 2) std::printf("note: one processor; no other thread can join\n");
  // The loop's work on the calling thread alone, for the speedups.
  std::vector<double> alone;
  for (int r = 0; r < 50; ++r) {
    const auto start = Clock::now();
    for (int i = 0; i < kChunks; ++i) busy(kChunkWork);
    alone.push_back(micro(Clock::now() - start));
  }
  const double alone_us = quantile(alone, 0.5);
  std::printf("one loop on one thread: %.1f us\n", alone_us);
  // oneTBB starts its workers at the first loop: warm up, so that the first gap's rounds do
  // not time their start (a run without this: no join in 61 % of the 2 us gap's loops).
  for (int r = 0; r < 100; ++r) tbb_round();
  nlohmann::json results = nlohmann::json::array();
  const double gaps_us[] = {2, 16, 80, 300, 1500};
  for (const double gap : gaps_us) {
    const auto gap_time = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::micro>(gap));
    std::vector<Round> tbb_rounds, spin_rounds;
    for (int r = 0; r < rounds; ++r) {
      busy(gap_time);
      tbb_rounds.push_back(tbb_round());
    }
    results.push_back(summarize("oneTBB", gap, tbb_rounds, alone_us));
    {
      SpinningHelper helper;
      for (int r = 0; r < rounds; ++r) {
        busy(gap_time);
        spin_rounds.push_back(helper.round());
      }
    }
    results.push_back(summarize("spinning", gap, spin_rounds, alone_us));
  }
  try {
    write_file_atomically(out, [&](std::ostream& s) {
      s << nlohmann::json{{"loop_alone_us", alone_us}, {"chunks", kChunks}, {"chunk_us", micro(kChunkWork)},
                          {"results", results}}.dump(2)
        << "\n";
    });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinew_bench_fork_join: %s\n", e.what());
    return 2;
  }
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
