#include "engine/core/cpu_features.hpp"

namespace sinew {
namespace {

bool cpu_has_avx2() {
  __builtin_cpu_init();  // callable before other static initialisers have run
  return __builtin_cpu_supports("avx2");
}

}  // namespace

namespace detail {
std::atomic<bool> g_use_avx2{cpu_has_avx2()};
}  // namespace detail

void allow_avx2(bool allowed) {
  static const bool has_avx2 = cpu_has_avx2();
  detail::g_use_avx2.store(allowed && has_avx2, std::memory_order_relaxed);
}

}  // namespace sinew
