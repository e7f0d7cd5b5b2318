#include "engine/core/cpu_features.hpp"

#include <atomic>

namespace sinew {
namespace {

std::atomic<bool> g_allowed{true};

}  // namespace

bool use_avx2() {
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  return has_avx2 && g_allowed.load(std::memory_order_relaxed);
}

void allow_avx2(bool allowed) { g_allowed.store(allowed, std::memory_order_relaxed); }

}  // namespace sinew
