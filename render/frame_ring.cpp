#include "render/frame_ring.hpp"

namespace sinew {

FrameRing::FrameRing(int slots, size_t bytes_per_slot)
    : m_buffers(size_t(slots < 1 ? 1 : slots), std::vector<uint8_t>(bytes_per_slot)) {}

uint8_t* FrameRing::acquire() {
  std::unique_lock lock(m_mutex);
  m_changed.wait(lock, [&] { return m_aborted || m_published - m_released < slots(); });
  return m_aborted ? nullptr : m_buffers[m_published % slots()].data();
}

void FrameRing::publish() {
  {
    std::lock_guard lock(m_mutex);
    ++m_published;
  }
  m_changed.notify_all();
}

void FrameRing::close() {
  {
    std::lock_guard lock(m_mutex);
    m_closed = true;
  }
  m_changed.notify_all();
}

const uint8_t* FrameRing::next() {
  std::unique_lock lock(m_mutex);
  m_changed.wait(lock, [&] { return m_aborted || m_closed || m_released < m_published; });
  if (m_aborted || m_released == m_published) return nullptr;
  return m_buffers[m_released % slots()].data();
}

void FrameRing::release() {
  {
    std::lock_guard lock(m_mutex);
    ++m_released;
  }
  m_changed.notify_all();
}

void FrameRing::abort() {
  {
    std::lock_guard lock(m_mutex);
    m_aborted = true;
  }
  m_changed.notify_all();
}

}  // namespace sinew
