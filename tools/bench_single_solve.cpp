// sinew_bench_single_solve: one right-hand side solved with a supernodal factor three ways,
// alternating call by call in one process (a noisy machine slows all alike): CHOLMOD's own
// solve (cholmod_solve2, one thread), the tree solve on the factor's values
// (supernodal_tree_solve.hpp: split over two threads where the elimination tree allows,
// else in order on one), and the same on a single-precision copy of the values (the
// preconditioner's solve of solver.stale_factor_precision "single"). Factors of 27-point
// grid operators with 3 unknowns a node (a hex lattice's pattern), ordered as LinearSolver
// orders them (AMD or nested dissection, the one with less fill). Medians and fastest calls
// in microseconds; JSON out.
#include <Eigen/CholmodSupport>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "engine/assembly/system_pattern.hpp"  // SparseMatrix
#include "engine/io/atomic_file.hpp"
#include "engine/solve/supernodal_tree_solve.hpp"
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

using Clock = std::chrono::steady_clock;

// 27 I_3 minus the 26-neighbour adjacency of an nx^3 grid, per node a 3 x 3 identity block:
// strictly diagonally dominant, so SPD.
SparseMatrix lattice_operator(int nx) {
  const auto node = [nx](int i, int j, int k) { return (k * nx + j) * nx + i; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nx; ++k)
    for (int j = 0; j < nx; ++j)
      for (int i = 0; i < nx; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || c < 0 || a >= nx || b >= nx || c >= nx) continue;
              const bool self = di == 0 && dj == 0 && dk == 0;
              for (int r = 0; r < 3; ++r)
                entries.emplace_back(3 * node(i, j, k) + r, 3 * node(a, b, c) + r, self ? 27.0 : -1.0);
            }
  SparseMatrix A(3 * nx * nx * nx, 3 * nx * nx * nx);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

struct SupernodalFactor : Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> {
  explicit SupernodalFactor(const SparseMatrix& A) {
    setMode(Eigen::CholmodSupernodalLLt);
    cholmod_common& common = cholmod();
    common.nmethods = 2;  // as LinearSolver::factorize: AMD or nested dissection
    common.method[0].ordering = CHOLMOD_AMD;
    common.method[1].ordering = CHOLMOD_NESDIS;
    compute(A);
  }
  cholmod_factor& L() const { return *m_cholmodFactor; }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[(v.size() - 1) / 2];
}

// The fastest call: on a VM shared with noisy neighbours, the least disturbed estimate of a
// pass's own cost (the median says what a caller sees).
double fastest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

}  // namespace

int main(int argc, char** argv) {
  cli::Options options("sinew_bench_single_solve [--repeats N] [--threads T] [--out FILE]",
                       "One right-hand side on supernodal factors of 27-point lattice operators (3 unknowns a\n"
                       "node; 375 to 12,288 unknowns): CHOLMOD's solve, the tree solve in double, and the tree\n"
                       "solve reading single-precision values, alternating call by call. Prints medians in\n"
                       "microseconds, whether the tree split over two threads, and how far the single-precision\n"
                       "solution is from the double one (relative 2-norm); also each path's fastest call.",
                       {{"--repeats", "N", "calls per path and case (default 300)"},
                        {"--threads", "T", "worker threads (default: all cores)"},
                        {"--out", "FILE", "JSON results (default bench_single_solve.json)"}},
                       0);
  int repeats = 300, threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::string out = "bench_single_solve.json";
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    repeats = options.get_int("--repeats", repeats, 1);
    threads = options.get_int("--threads", threads, 1);
    out = options.get("--out", out);
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_single_solve: %s\n", e.what());
    return 2;
  }
  const tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  nlohmann::json cases = nlohmann::json::array();
  for (const int nx : {5, 9, 11, 14, 16}) {
    const SparseMatrix A = lattice_operator(nx);
    const SupernodalFactor factor(A);
    if (factor.info() != Eigen::Success) {
      std::fprintf(stderr, "sinew_bench_single_solve: the factorisation failed (nx %d)\n", nx);
      return 1;
    }
    cholmod_factor& L = factor.L();
    SupernodalTreeSolve tree;
    tree.analyse(L);
    if (!tree.ordered()) {
      std::fprintf(stderr, "sinew_bench_single_solve: the factor's supernodes are not in order (nx %d)\n", nx);
      return 1;
    }
    const int n = static_cast<int>(A.rows());
    const double* values = static_cast<const double*>(L.x);
    const std::vector<float> single(values, values + L.xsize);
    const VecX b = VecX::Random(n);
    VecX x_cholmod(n), x_double(n), x_single(n);
    cholmod_common common;
    cholmod_start(&common);
    cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
    cholmod_dense rhs{};
    rhs.nrow = n, rhs.ncol = 1, rhs.d = n, rhs.nzmax = n, rhs.xtype = CHOLMOD_REAL, rhs.dtype = CHOLMOD_DOUBLE;
    rhs.x = const_cast<double*>(b.data());
    std::vector<double> times[3];
    for (int r = 0; r < repeats; ++r)
      for (int path = 0; path < 3; ++path) {
        const auto start = Clock::now();
        if (path == 0) {
          cholmod_solve2(CHOLMOD_A, &L, &rhs, nullptr, &x, nullptr, &y, &e, &common);
        } else if (path == 1) {
          tree.solve(L, b.data(), x_double.data());
        } else {
          tree.solve(L, single.data(), b.data(), x_single.data());
        }
        times[path].push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
      }
    x_cholmod = Eigen::Map<const VecX>(static_cast<const double*>(x->x), n);
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_finish(&common);
    const double tree_error = (x_double - x_cholmod).norm() / x_cholmod.norm();
    const double single_error = (x_single - x_double).norm() / x_double.norm();
    const double cholmod_us = median(times[0]), double_us = median(times[1]), single_us = median(times[2]);
    std::printf("n %6d, factor %8ld entries, tree %s: CHOLMOD %8.1f us, tree double %8.1f us, tree single %8.1f us "
                "(fastest %.1f, %.1f, %.1f; single vs double %.1e, tree vs CHOLMOD %.1e)\n",
                n, static_cast<long>(L.xsize), tree.usable() ? "split" : "whole", cholmod_us, double_us, single_us,
                fastest(times[0]), fastest(times[1]), fastest(times[2]), single_error, tree_error);
    cases.push_back({{"unknowns", n}, {"factor_entries", static_cast<long>(L.xsize)}, {"split", tree.usable()},
                     {"cholmod_us", cholmod_us}, {"tree_double_us", double_us}, {"tree_single_us", single_us},
                     {"fastest_cholmod_us", fastest(times[0])}, {"fastest_tree_double_us", fastest(times[1])},
                     {"fastest_tree_single_us", fastest(times[2])},
                     {"single_vs_double_relative", single_error}, {"tree_vs_cholmod_relative", tree_error}});
  }
  write_file_atomically(out, [&](std::ostream& s) {
    s << nlohmann::json{{"threads", threads}, {"repeats", repeats}, {"cases", cases}}.dump(2) << "\n";
  });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
