#include "ui/session_runner.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <memory>

#include "engine/core/error.hpp"
#include "engine/core/progress.hpp"
#include "engine/realtime/realtime_loop.hpp"
#include "engine/simulate_frame.hpp"
#include "render/image.hpp"
#include "render/renderer.hpp"
#include "render/video_recorder.hpp"
#include "ui/imgui_layer.hpp"
#include "ui/panel.hpp"
#include "ui/session_quantities.hpp"
#include "ui/surface_pick.hpp"

namespace sinew {
namespace {

// A change of the pointer scheduled for a frame: a position, a button state, or both.
struct PointerChange {
  std::optional<Eigen::Vector2f> position;
  std::optional<bool> down;
};

// The grabbed point's target moving along a straight path.
struct GrabPath {
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();
  int start = 0, frames = 1;
};

class Session {
 public:
  Session(const SessionScript& script, const SessionOptions& options, std::ostream& log)
      : m_script(script), m_options(options), m_log(log), m_live(load_scene(script.scene_path)),
        m_renderer(render_options(script)) {
    if (!script.body.empty()) m_live.select_body(script.body);
    m_frames = script.frames > 0 ? script.frames : m_live.scene().frames;
    m_threads = options.threads > 0 ? options.threads : int(tbb::info::default_concurrency());
    m_threads_control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                              size_t(m_threads));
    if (script.panel) m_layer = std::make_unique<ImGuiLayer>(script.width, script.height);
    schedule_events();
    if (!options.record_path.empty()) start_recording(options.record_path);
  }

  SessionResult run() {
    Progress progress("session", m_frames, m_options.progress ? stderr : nullptr);
    // Frame 0 is the initial state: drawn (which frames the camera and lays out the panel,
    // so that frame-0 events find pixels and widgets), not simulated.
    draw();
    for (int f = 0; f <= m_frames; ++f) {
      m_frame = f;
      for (const SessionEvent* e : m_at[f]) apply(*e);
      apply_pointer_changes(f);
      update_grab_target(f);
      if (f > 0 && (!m_paused || m_step_once)) {
        m_step_once = false;
        if (!simulate()) break;
      }
      draw();
      if (m_video) m_video->add_frame([&](uint8_t* rgb) { m_renderer.read_rgb(rgb); });
      for (const SessionEvent* e : m_after[f]) check(*e);
      m_result.frames = f;
      progress.update(f);
    }
    if (m_video) stop_recording();
    m_result.state_hash = m_live.world().state_hash();
    return m_result;
  }

 private:
  static RenderOptions render_options(const SessionScript& script) {
    RenderOptions o;
    o.width = script.width, o.height = script.height;
    return o;
  }

  [[noreturn]] void fail(const SessionEvent& e, const std::string& what) const {
    throw InputError(m_script.name + ": " + e.path + " (frame " + std::to_string(m_frame) + "): " + what);
  }

  // Events by frame; screenshots and expectations go after the frame is simulated and drawn.
  void schedule_events() {
    const double fps = m_live.scene().fps;
    for (const SessionEvent& e : m_script.events) {
      const int frame = e.frame >= 0 ? e.frame : int(std::lround(e.time * fps));
      if (frame > m_frames)
        throw InputError(m_script.name + ": " + e.path + ": frame " + std::to_string(frame) +
                         " is after the last frame (" + std::to_string(m_frames) + ")");
      const bool after = e.type == SessionEventType::Screenshot || e.type == SessionEventType::Expect;
      (after ? m_after : m_at)[frame].push_back(&e);
    }
  }

  Eigen::Vector2f widget_centre(const SessionEvent& e) const {
    WidgetRect r;
    if (!m_layer) fail(e, "widget '" + e.widget + "': the panel is off (\"panel\": false)");
    if (!m_panel.widget_rect(e.widget, r)) fail(e, "no widget labelled '" + e.widget + "' on the panel");
    return {0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1)};
  }

  void apply(const SessionEvent& e) {
    using T = SessionEventType;
    const int f = m_frame;
    switch (e.type) {
      case T::Pointer: {
        PointerChange c;
        c.position = e.pixel ? *e.pixel : widget_centre(e);
        if (e.action != "move") c.down = e.action == "press";
        m_pointer_changes[f].push_back(c);
        break;
      }
      case T::Click: {
        const Eigen::Vector2f at = widget_centre(e);
        m_pointer_changes[f].push_back({at, false});
        m_pointer_changes[f + 1].push_back({at, true});
        m_pointer_changes[f + 2].push_back({at, false});
        break;
      }
      case T::DragSlider: {
        const Eigen::Vector2f centre = widget_centre(e);
        float from = 0, to = 0;
        if (!m_panel.slider_x(e.widget, m_live.parameter(e.widget), from) || !m_panel.slider_x(e.widget, e.value, to))
          fail(e, "widget '" + e.widget + "' is not a parameter slider");
        m_pointer_changes[f].push_back({Eigen::Vector2f(from, centre.y()), false});
        m_pointer_changes[f + 1].push_back({Eigen::Vector2f(from, centre.y()), true});
        for (int k = 1; k <= e.frames; ++k)
          m_pointer_changes[f + 1 + k].push_back({Eigen::Vector2f(from + (to - from) * float(k) / float(e.frames), centre.y()), {}});
        m_pointer_changes[f + 2 + e.frames].push_back({{}, false});
        break;
      }
      case T::Key:
        if (e.key == "space") m_paused = !m_paused;
        else if (e.key == "s") m_step_once = true;
        else if (e.key == "r") reset();
        else toggle_recording(e);
        break;
      case T::Grab: {
        std::optional<Attachment> grab;
        const State& state = m_live.world().state();
        if (e.pixel) {
          Vec3 origin, direction;
          pixel_ray(m_renderer.camera(), e.pixel->x(), e.pixel->y(), m_script.width, m_script.height, origin, direction);
          grab = pick_surface(m_live.world().model(), state, origin, direction);
          if (!grab) fail(e, "no surface under pixel [" + std::to_string(e.pixel->x()) + ", " + std::to_string(e.pixel->y()) + "]");
        } else {
          grab = nearest_surface_vertex(m_live.world().model(), state, *e.point);
        }
        m_grab = grab;
        m_grab_path.reset();
        m_log << "session: frame " << f << ": grabbed body '" << m_live.world().model().bodies[size_t(grab->body)].name
              << "' vertex " << grab->vertex << " at (" << grab->target.transpose() << ")\n";
        break;
      }
      case T::DragGrab:
        if (!m_grab) fail(e, "drag_grab needs a grab first");
        m_grab_path = GrabPath{m_grab->target, *e.point, f, e.frames};
        break;
      case T::Release:
        m_grab.reset();
        m_grab_path.reset();
        break;
      case T::Camera: m_renderer.set_orbit(e.orbit_deg, e.elevation_deg); break;
      case T::Set:
        try {
          set_parameter(e.parameter, e.value, e.text);
        } catch (const InputError& error) {
          fail(e, error.what());
        }
        break;
      case T::RecordStart:
        if (m_video) fail(e, "already recording");
        if (e.file.empty() && m_options.record_path.empty()) fail(e, "record_start needs \"path\" or --record");
        start_recording(e.file.empty() ? m_options.record_path : e.file);
        break;
      case T::RecordStop:
        if (!m_video) fail(e, "not recording");
        stop_recording();
        break;
      case T::Screenshot:
      case T::Expect: break;
    }
  }

  void set_parameter(const std::string& name, double value, const std::string& text) {
    if (name == "material_model") m_live.set_material_model(text);
    else if (name == "strain_mode") m_live.set_strain_mode(text);
    else m_live.set_parameter(name, value);
  }

  void apply_pointer_changes(int f) {
    const auto it = m_pointer_changes.find(f);
    if (it == m_pointer_changes.end()) return;
    for (const PointerChange& c : it->second) {
      if (c.position) m_pointer.x = c.position->x(), m_pointer.y = c.position->y();
      if (c.down) m_pointer.down = *c.down;
    }
    m_pointer_changes.erase(it);
  }

  void update_grab_target(int f) {
    if (!m_grab || !m_grab_path) return;
    const double s = std::clamp(double(f - m_grab_path->start) / m_grab_path->frames, 0.0, 1.0);
    m_grab->target = m_grab_path->from + s * (m_grab_path->to - m_grab_path->from);
  }

  bool simulate() {
    World& world = m_live.world();
    world.mutable_state().attachments.clear();
    if (m_grab) world.mutable_state().attachments.push_back(*m_grab);
    // A budget (panel or "set budget_ms") makes the caps follow the wall clock; none: the
    // scene's caps, deterministic.
    if (!m_loop || m_loop_budget != m_live.budget_ms()) {
      RealtimeSettings settings;
      settings.budget_ms = m_live.budget_ms();
      m_loop = std::make_unique<RealtimeLoop>(m_live.scene().solver, settings);
      m_loop_budget = m_live.budget_ms();
    }
    m_last = m_loop->frame(world, m_live.scene().steps_per_frame());
    m_stats.over_budget = m_loop->counters().over_budget;
    m_stats.step_ms.push_back(m_last.step_ms);
    if (m_stats.step_ms.size() > 120) m_stats.step_ms.pop_front();
    m_stats.stages = m_last.stages;
    for (const auto& [stage, ms] : m_last.stages) {
      std::deque<double>& series = m_stats.stage_ms[stage];  // aligned with step_ms
      series.push_back(ms);
      while (series.size() > m_stats.step_ms.size()) series.pop_front();
      while (series.size() < m_stats.step_ms.size()) series.push_front(0.0);  // first seen now
    }
    m_stats.rows = m_last.rows;
    m_stats.violation = m_last.violation;
    m_stats.iterations = m_last.iterations;
    m_sim_seconds += m_live.scene().h * m_live.scene().steps_per_frame();
    m_wall_ms += m_last.step_ms;
    m_stats.sim_per_wall = m_wall_ms > 0 ? m_sim_seconds / (m_wall_ms * 1e-3) : 0;
    if (m_last.finite) return true;
    m_result.finite = false;
    m_log << "session: frame " << m_frame << ": the step failed (non-finite state or divergence); stopped\n";
    return false;
  }

  void draw() {
    m_stats.paused = m_paused, m_stats.recording = bool(m_video), m_stats.threads = m_threads;
    m_stats.timings = m_script.timings;
    PanelRequests requests;
    const World& world = m_live.world();
    if (!m_layer) {
      m_renderer.draw(world.model(), world.state());
      return;
    }
    const double dt = 1.0 / m_live.scene().fps;
    m_renderer.draw(world.model(), world.state(), [&] {
      m_layer->frame(m_pointer, dt, [&] { requests = m_panel.draw(m_live, m_stats); });
    });
    apply(requests);
  }

  void apply(const PanelRequests& r) {
    if (r.toggle_pause) m_paused = !m_paused;
    if (r.step) m_step_once = true;
    if (r.reset) reset();
    if (r.toggle_record) {
      if (m_video) stop_recording();
      else if (!m_options.record_path.empty()) start_recording(m_options.record_path);
      else m_log << "session: frame " << m_frame << ": Record pressed without --record: nothing to record to\n";
    }
    try {
      for (const auto& [name, value] : r.parameters) {
        m_live.set_parameter(name, value);
        m_log << "session: frame " << m_frame << ": " << name << " = " << value << "\n";
      }
      if (!r.material_model.empty()) m_live.set_material_model(r.material_model);
      if (!r.strain_mode.empty()) m_live.set_strain_mode(r.strain_mode);
    } catch (const InputError& e) {
      // A value the panel allows but the scene rejects: the run goes on unchanged.
      m_log << "session: frame " << m_frame << ": panel edit refused: " << e.what() << "\n";
    }
    if (r.threads > 0 && r.threads != m_threads) {
      m_threads = r.threads;
      m_threads_control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                                size_t(m_threads));
    }
  }

  void reset() {
    m_live.reset();
    m_grab.reset();
    m_grab_path.reset();
  }

  void toggle_recording(const SessionEvent& e) {
    if (m_video) stop_recording();
    else if (!m_options.record_path.empty()) start_recording(m_options.record_path);
    else fail(e, "key 'c' starts recording, which needs --record");
  }

  void start_recording(const std::string& path) {
    VideoSettings settings;
    settings.path = path;
    settings.format = {m_script.width, m_script.height, m_live.scene().fps};
    m_video = std::make_unique<VideoRecorder>(settings);
    m_video_path = path;
  }

  void stop_recording() {
    m_video->finish();
    m_log << "session: video " << m_video_path << " (" << m_video->frames() << " frames)\n";
    m_video.reset();
  }

  void check(const SessionEvent& e) {
    if (e.type == SessionEventType::Screenshot) {
      write_png(e.file, m_renderer.image());
      m_log << "session: frame " << m_frame << ": screenshot " << e.file << "\n";
      return;
    }
    const SessionSnapshot snapshot{m_live, m_last, m_grab ? &*m_grab : nullptr};
    const double value = session_quantity(e.quantity, snapshot, m_script.name + ": " + e.path);
    const bool ok = (!e.below || value < *e.below) && (!e.above || value > *e.above);
    ++m_result.expectations;
    m_result.measured[e.path] = value;
    m_result.failed += !ok;
    m_log << "session: frame " << m_frame << ": expect " << e.quantity << " = " << value;
    if (e.above) m_log << " > " << *e.above;
    if (e.below) m_log << " < " << *e.below;
    m_log << (ok ? ": ok" : ": FAILED") << " (" << e.path << ")\n";
  }

  const SessionScript& m_script;
  const SessionOptions& m_options;
  std::ostream& m_log;
  LiveScene m_live;
  Renderer m_renderer;
  std::unique_ptr<ImGuiLayer> m_layer;
  Panel m_panel;
  PanelStats m_stats;
  FrameStats m_last;
  std::unique_ptr<tbb::global_control> m_threads_control;
  std::unique_ptr<VideoRecorder> m_video;
  std::unique_ptr<RealtimeLoop> m_loop;
  double m_loop_budget = -1;
  std::string m_video_path;
  std::map<int, std::vector<const SessionEvent*>> m_at, m_after;
  std::map<int, std::vector<PointerChange>> m_pointer_changes;
  Pointer m_pointer;
  std::optional<Attachment> m_grab;
  std::optional<GrabPath> m_grab_path;
  SessionResult m_result;
  int m_frames = 0, m_frame = 0, m_threads = 1;
  bool m_paused = false, m_step_once = false;
  double m_sim_seconds = 0, m_wall_ms = 0;
};

}  // namespace

SessionResult run_session(const SessionScript& script, const SessionOptions& options, std::ostream& log) {
  Session session(script, options, log);
  return session.run();
}

}  // namespace sinew
