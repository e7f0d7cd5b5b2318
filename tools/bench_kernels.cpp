// sinew_bench_kernels: the hand-vectorised kernels against their baseline paths
// (engine/core/cpu_features.hpp): add_scaled (PGS's column update) and the supernodal block
// solve's passes, on the 7-point grid Laplacian's supernodal factor, 4, 8 and 16 right-hand
// sides. The two paths alternate call by call in one process, so a noisy machine slows both
// alike; medians, JSON out. Both paths give the same bits, which is checked here too.
#include <Eigen/CholmodSupport>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "engine/core/cpu_features.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/math/add_scaled.hpp"
#include "engine/solve/supernodal_block_solve.hpp"
#include "tests/support/grid_matrices.hpp"  // the solver tests' grid Laplacian
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

using Clock = std::chrono::steady_clock;

struct SupernodalFactor : Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> {
  explicit SupernodalFactor(const SparseMatrix& A) {
    setMode(Eigen::CholmodSupernodalLLt);
    compute(A);
  }
  const cholmod_factor& L() const { return *m_cholmodFactor; }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[(v.size() - 1) / 2];
}

// Times `run(avx2)` alternately on both paths; medians in microseconds.
template <typename Run>
std::pair<double, double> alternate(int repeats, const Run& run) {
  std::vector<double> times[2];
  for (int r = 0; r < 2 * repeats; ++r) {
    const bool avx2 = r % 2 == 1;
    const auto start = Clock::now();
    if (avx2) {
      run();
    } else {
      const BaselineKernelsOnly baseline;
      run();
    }
    times[avx2].push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  return {median(times[0]), median(times[1])};
}

}  // namespace

int main(int argc, char** argv) {
  cli::Options options("sinew_bench_kernels [--repeats N] [--out FILE]",
                       "The AVX2 kernels against their baseline (SSE2) paths, alternating call by call:\n"
                       "add_scaled over 330 and 3,000 entries, and the supernodal block solve on grid factors\n"
                       "of 512, 1,728 and 4,096 unknowns with 4, 8 and 16 right-hand sides. Prints medians in\n"
                       "microseconds and checks that both paths give the same bits (exit code 1 if not).",
                       {{"--repeats", "N", "calls per path and case (default 200)"},
                        {"--out", "FILE", "JSON results (default bench_kernels.json)"}},
                       0);
  int repeats = 200;
  std::string out = "bench_kernels.json";
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    repeats = options.get_int("--repeats", repeats, 1);
    out = options.get("--out", out);
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_kernels: %s\n", e.what());
    return 2;
  }
  const bool has_avx2 = use_avx2();
  std::printf("AVX2 on this CPU: %s\n", has_avx2 ? "yes" : "no (both columns time the baseline)");
  nlohmann::json cases = nlohmann::json::array();
  bool same_bits = true;
  for (const int n : {330, 3000}) {
    const VecX x = VecX::Random(n);
    VecX y = VecX::Random(n);
    const auto [baseline, avx2] = alternate(repeats, [&] {
      for (int k = 0; k < 100; ++k) add_scaled(y.data(), x.data(), k % 2 ? 1e-3 : -1e-3, n);
    });
    std::printf("add_scaled        n %5d x 100 calls: baseline %8.2f us, avx2 %8.2f us\n", n, baseline, avx2);
    cases.push_back({{"kernel", "add_scaled"}, {"n", n}, {"calls", 100}, {"baseline_us", baseline}, {"avx2_us", avx2}});
  }
  for (const int nx : {8, 12, 16}) {
    const SparseMatrix A = test::grid_laplacian(nx);
    const SupernodalFactor factor(A);
    if (factor.info() != Eigen::Success) {
      std::fprintf(stderr, "sinew_bench_kernels: the grid factorisation failed\n");
      return 1;
    }
    SupernodalBlockSolve solve;
    solve.analyse(factor.L());
    SupernodalBlockSolve::Workspace ws;
    solve.prepare(ws);
    const int n = static_cast<int>(A.rows());
    for (const int width : {4, 8, 16}) {
      const MatX B = MatX::Random(n, width);
      MatX X(n, width), X_baseline(n, width);
      const auto [baseline, avx2] = alternate(repeats, [&] { solve.solve(factor.L(), B.data(), n, X.data(), n, width, ws); });
      solve.solve(factor.L(), B.data(), n, X.data(), n, width, ws);
      {
        const BaselineKernelsOnly only;
        solve.solve(factor.L(), B.data(), n, X_baseline.data(), n, width, ws);
      }
      const bool same = std::memcmp(X.data(), X_baseline.data(), sizeof(double) * X.size()) == 0;
      same_bits = same_bits && same;
      std::printf("block solve   n %5d, %2d columns: baseline %8.2f us, avx2 %8.2f us%s\n", n, width, baseline, avx2,
                  same ? "" : "  (DIFFERENT BITS)");
      cases.push_back({{"kernel", "supernodal_block_solve"}, {"n", n}, {"columns", width}, {"baseline_us", baseline},
                       {"avx2_us", avx2}, {"same_bits", same}});
    }
  }
  write_file_atomically(out, [&](std::ostream& s) {
    s << nlohmann::json{{"avx2", has_avx2}, {"repeats", repeats}, {"cases", cases}}.dump(2) << "\n";
  });
  std::printf("wrote %s\n", out.c_str());
  return same_bits ? 0 : 1;
}
