#include "render/video_recorder.hpp"

#include "render/image.hpp"
#include "render/render_error.hpp"

namespace sinew {

VideoRecorder::VideoRecorder(const VideoSettings& settings) : m_settings(settings) {
  const std::string ffmpeg = settings.ffmpeg.empty() ? require_ffmpeg() : settings.ffmpeg;
  m_encoder = std::make_unique<FfmpegEncoder>(settings.format, ffmpeg, settings.path);
  const size_t bytes = size_t(3) * settings.format.width * settings.format.height;
  m_rows.resize(bytes);
  if (settings.capture_thread) {
    m_ring = std::make_unique<FrameRing>(settings.ring_slots, bytes);
    m_thread = std::thread([this] { consume(); });
  } else {
    m_gl_rows.resize(bytes);
  }
}

VideoRecorder::~VideoRecorder() {
  if (m_ring) m_ring->abort();
  join();
  // m_encoder's destructor stops ffmpeg and removes the temporary file if not finished.
}

void VideoRecorder::join() {
  if (m_thread.joinable()) m_thread.join();
}

void VideoRecorder::consume() {
  try {
    while (const uint8_t* frame = m_ring->next()) {
      flip_rows(frame, m_rows.data(), m_settings.format.width, m_settings.format.height);
      m_ring->release();  // free the slot before the (slow) write so the caller rarely waits
      m_encoder->write_frame(m_rows.data());
    }
  } catch (...) {
    m_error = std::current_exception();
    m_ring->abort();
  }
}

void VideoRecorder::add_frame(const std::function<void(uint8_t*)>& fill) {
  if (!m_encoder) throw RenderError("video '" + m_settings.path + "': frame added after finish()");
  if (m_ring) {
    uint8_t* slot = m_ring->acquire();
    if (!slot) {  // only the capture thread aborts the ring while we record
      join();
      std::rethrow_exception(m_error);
    }
    fill(slot);
    m_ring->publish();
  } else {
    fill(m_gl_rows.data());
    flip_rows(m_gl_rows.data(), m_rows.data(), m_settings.format.width, m_settings.format.height);
    m_encoder->write_frame(m_rows.data());
  }
  ++m_frames;
}

void VideoRecorder::finish() {
  if (m_ring) {
    m_ring->close();
    join();
    if (m_error) std::rethrow_exception(m_error);
  }
  m_encoder->finish();
  m_encoder.reset();
}

}  // namespace sinew
