#include "engine/solve/cholmod_memory_pool.hpp"

#include <SuiteSparse_config.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace sinew {
namespace {

// Each block starts with a header (padded to 32 bytes, keeping the payload as aligned as
// malloc's) holding a tag and the block's size class.
constexpr uint64_t kTag = 0x73696e6577706f6fULL;  // marks a pool block
constexpr std::size_t kHeader = 32;
constexpr int kClasses = 48;  // payload capacity 2^c bytes

struct Header {
  uint64_t tag;
  int size_class;
  Header* next;  // in a free list
};
static_assert(sizeof(Header) <= kHeader);

// Free blocks per class as intrusive lists through their headers: freeing never allocates.
struct Pool {
  std::mutex mutex;
  std::array<Header*, kClasses> free{};
  std::array<long, kClasses> count{};
};

Pool& pool() {
  static Pool* p = new Pool;  // never destroyed: CHOLMOD may free after static destructors
  return *p;
}

int size_class(std::size_t bytes) {
  int c = 4;
  while ((std::size_t{1} << c) < bytes) ++c;
  return c;
}

Header* header_of(void* payload) { return reinterpret_cast<Header*>(static_cast<char*>(payload) - kHeader); }

void* pool_malloc(std::size_t bytes) {
  const int c = size_class(bytes == 0 ? 1 : bytes);
  if (c >= kClasses) return nullptr;
  void* raw = nullptr;
  {
    std::lock_guard<std::mutex> lock(pool().mutex);
    Header*& head = pool().free[c];
    if (head) {
      raw = head;
      head = head->next;
      --pool().count[c];
    }
  }
  if (!raw) {
    raw = std::malloc(kHeader + (std::size_t{1} << c));
    if (!raw) return nullptr;
    Header* h = static_cast<Header*>(raw);
    h->tag = kTag;
    h->size_class = c;
  }
  return static_cast<char*>(raw) + kHeader;
}

void pool_free(void* payload) {
  if (!payload) return;
  Header* h = header_of(payload);
  // Blocks from before the pool have no header: their 32 bytes before the payload are
  // malloc's own bookkeeping, which never holds the tag at a valid class.
  if (h->tag != kTag || h->size_class < 4 || h->size_class >= kClasses) {
    std::free(payload);
    return;
  }
  std::lock_guard<std::mutex> lock(pool().mutex);
  h->next = pool().free[h->size_class];
  pool().free[h->size_class] = h;
  ++pool().count[h->size_class];
}

void* pool_calloc(std::size_t count, std::size_t size) {
  const std::size_t bytes = count * size;
  if (size != 0 && bytes / size != count) return nullptr;
  void* p = pool_malloc(bytes);
  if (p) std::memset(p, 0, bytes);
  return p;
}

void* pool_realloc(void* payload, std::size_t bytes) {
  if (!payload) return pool_malloc(bytes);
  Header* h = header_of(payload);
  if (h->tag != kTag) return std::realloc(payload, bytes);
  const std::size_t capacity = std::size_t{1} << h->size_class;
  if (bytes <= capacity) return payload;
  void* grown = pool_malloc(bytes);
  if (!grown) return nullptr;
  std::memcpy(grown, payload, capacity);
  pool_free(payload);
  return grown;
}

}  // namespace

void install_cholmod_memory_pool() {
  static std::once_flag once;
  std::call_once(once, [] {
    SuiteSparse_config.malloc_func = pool_malloc;
    SuiteSparse_config.calloc_func = pool_calloc;
    SuiteSparse_config.realloc_func = pool_realloc;
    SuiteSparse_config.free_func = pool_free;
  });
}

CholmodPoolStats cholmod_memory_pool_stats() {
  CholmodPoolStats stats;
  std::lock_guard<std::mutex> lock(pool().mutex);
  for (int c = 0; c < kClasses; ++c) {
    stats.free_blocks += pool().count[c];
    stats.free_bytes += pool().count[c] << c;
  }
  return stats;
}

}  // namespace sinew
