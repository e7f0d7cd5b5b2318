#pragma once
// Buffers a function keeps from one call to the next (so that a warm step allocates
// nothing), owned by the caller rather than thread_local. The row builders run as tasks
// (tbb::parallel_invoke) on whichever thread is free, and a thread_local buffer first used
// by a worker after warm-up allocated (beside the unit tests as load, the allocation test
// failed in 7 of 36 runs: add_strain_limit_rows on a TBB worker, in the flat finger's window).
// T may be incomplete where a KeptStorage<T> is declared or destroyed; get() needs it whole,
// so a builder's buffers stay private to its .cpp.
#include <memory>

namespace sinew {

template <typename T>
class KeptStorage {
 public:
  KeptStorage() = default;
  // A copy starts empty: the buffers hold nothing a later call reads, except a deferred
  // strain build's SVDs, which its completion reads in the same SQP iteration (no copy of
  // the State comes in between; strain_limit_rows.hpp).
  KeptStorage(const KeptStorage&) {}
  KeptStorage& operator=(const KeptStorage&) { return *this; }
  KeptStorage(KeptStorage&&) noexcept = default;
  KeptStorage& operator=(KeptStorage&&) noexcept = default;

  T& get() {
    if (!m_value) m_value = Owned(new T(), [](T* p) { delete p; });
    return *m_value;
  }

 private:
  using Owned = std::unique_ptr<T, void (*)(T*)>;
  Owned m_value{nullptr, nullptr};
};

// The caller's buffers, or, for a caller without any (tests, tools, one-off queries), this
// thread's.
template <typename T>
T& kept_or_thread_local(KeptStorage<T>* storage) {
  if (storage) return storage->get();
  // Declared after the test: a thread_local's first use registers its destructor, which
  // glibc records with calloc, so a caller with buffers must not touch it.
  thread_local KeptStorage<T> own;
  return own.get();
}

}  // namespace sinew
