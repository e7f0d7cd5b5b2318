#include "engine/core/cpu_features.hpp"

namespace sinew {
namespace {

bool cpu_has_avx2() {
  __builtin_cpu_init();  // callable before other static initialisers have run
  return __builtin_cpu_supports("avx2");
}

const bool kCpuHasAvx2 = cpu_has_avx2();  // initialised before g_use_avx2 below (same file)

}  // namespace

namespace detail {
std::atomic<bool> g_use_avx2{kCpuHasAvx2};
}  // namespace detail

void allow_avx2(bool allowed) { detail::g_use_avx2.store(allowed && kCpuHasAvx2, std::memory_order_relaxed); }

}  // namespace sinew
