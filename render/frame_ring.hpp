#pragma once
// A fixed ring of equal byte buffers passed from one producer thread to one consumer thread
// in order. Memory is allocated once: a video of any length uses `slots` frames.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

namespace sinew {

class FrameRing {
 public:
  FrameRing(int slots, size_t bytes_per_slot);

  // Producer: the next slot to fill, waiting while every slot is in use; nullptr once aborted.
  uint8_t* acquire();
  // Producer: the slot from acquire() is ready for the consumer.
  void publish();
  // Producer: no more frames; the consumer drains what is published, then gets nullptr.
  void close();

  // Consumer: the oldest published slot, waiting for one; nullptr when closed and drained,
  // or aborted.
  const uint8_t* next();
  // Consumer: the slot from next() may be filled again.
  void release();

  // Either side: stop now (a failure); both sides' waits return nullptr.
  void abort();

  int slots() const { return int(m_buffers.size()); }

 private:
  std::vector<std::vector<uint8_t>> m_buffers;
  std::mutex m_mutex;
  std::condition_variable m_changed;
  long m_published = 0, m_released = 0;  // slot of frame k is k % slots
  bool m_closed = false, m_aborted = false;
};

}  // namespace sinew
