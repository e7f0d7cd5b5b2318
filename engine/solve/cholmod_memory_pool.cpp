#include "engine/solve/cholmod_memory_pool.hpp"

#include <SuiteSparse_config.h>

#include <array>
#include <cassert>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace sinew {
namespace {

// Each block starts with a header (padded to 32 bytes, keeping the payload as aligned as
// malloc's) holding a tag and the block's size class. Blocks above kLargestClass bytes
// (a big supernodal factor) are malloc'd at their size and freed at once: rounding them up
// to a power of two could double them, and keeping them would hold their peak for good.
constexpr uint64_t kTag = 0x73696e6577706f6fULL;  // marks a pool block (checked in debug builds)
constexpr std::size_t kHeader = 32;
constexpr int kLargestClass = 26;  // 64 MiB
constexpr int kDirect = -1;        // size_class of a block not kept

struct Header {
  uint64_t tag;
  int size_class;  // payload capacity 2^size_class bytes, or kDirect
  std::size_t bytes;  // payload size of a kDirect block
  Header* next;    // in a free list
};
static_assert(sizeof(Header) <= kHeader);

// Free blocks per class as intrusive lists through their headers: freeing never allocates.
struct Pool {
  std::mutex mutex;
  std::array<Header*, kLargestClass + 1> free{};
  std::array<long, kLargestClass + 1> count{};
};

Pool& pool() {
  static Pool* p = new Pool;  // never destroyed: CHOLMOD may free after static destructors
  return *p;
}

int size_class(std::size_t bytes) {
  int c = 4;
  while (c <= kLargestClass && (std::size_t{1} << c) < bytes) ++c;
  return c <= kLargestClass ? c : kDirect;
}

// Every block CHOLMOD frees is one of the pool's: it is installed before any SuiteSparse
// call (install_cholmod_memory_pool), so the header is always there to read.
Header* header_of(void* payload) {
  Header* h = reinterpret_cast<Header*>(static_cast<char*>(payload) - kHeader);
  assert(h->tag == kTag && "a block not from the CHOLMOD pool");
  return h;
}

std::size_t capacity_of(const Header* h) {
  return h->size_class == kDirect ? h->bytes : std::size_t{1} << h->size_class;
}

void* pool_malloc(std::size_t bytes) {
  const int c = size_class(bytes == 0 ? 1 : bytes);
  void* raw = nullptr;
  if (c != kDirect) {
    std::lock_guard<std::mutex> lock(pool().mutex);
    Header*& head = pool().free[c];
    if (head) {
      raw = head;
      head = head->next;
      --pool().count[c];
    }
  }
  if (!raw) {
    raw = std::malloc(kHeader + (c == kDirect ? bytes : std::size_t{1} << c));
    if (!raw) return nullptr;
    Header* h = static_cast<Header*>(raw);
    h->tag = kTag;
    h->size_class = c;
    h->bytes = bytes;
  }
  return static_cast<char*>(raw) + kHeader;
}

void pool_free(void* payload) {
  if (!payload) return;
  Header* h = header_of(payload);
  if (h->size_class == kDirect) {
    std::free(h);
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
  const std::size_t capacity = capacity_of(header_of(payload));
  if (bytes <= capacity) return payload;
  void* grown = pool_malloc(bytes);
  if (!grown) return nullptr;
  std::memcpy(grown, payload, capacity);
  pool_free(payload);
  return grown;
}

// Installed before main, so that not even a CHOLMOD call made before the first
// LinearSolver allocates outside the pool.
const bool installed_at_start = (install_cholmod_memory_pool(), true);

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
  for (int c = 0; c <= kLargestClass; ++c) {
    stats.free_blocks += pool().count[c];
    stats.free_bytes += pool().count[c] << c;
  }
  return stats;
}

}  // namespace sinew
