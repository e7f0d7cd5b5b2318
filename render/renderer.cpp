#include "render/renderer.hpp"

#include <Eigen/Geometry>
#include <algorithm>

#include "engine/analysis/element_fields.hpp"
#include "render/egl_context.hpp"
#include "render/framebuffer.hpp"
#include "render/ground_pass.hpp"
#include "render/legend_pass.hpp"
#include "render/render_error.hpp"
#include "render/surface_pass.hpp"
#include "render/wireframe_pass.hpp"

namespace sinew {

struct Renderer::Impl {
  RenderOptions options;
  EglContext context;  // first member: destroyed last, after every GL object
  Framebuffer framebuffer;
  GroundPass ground;
  SurfacePass surfaces;
  WireframePass wireframe;
  LegendPass legend;

  bool framed = false;
  Aabb framed_box;  // what the camera frames: every framing box seen since reset_view()
  ViewSetup view;
  ColorScale scale;
  bool have_scale = false;
  LegendBox legend_box;
  std::vector<std::vector<double>> vertex_values;

  explicit Impl(const RenderOptions& o) : options(o), framebuffer(o.width, o.height, o.samples) {}

  // Frames the scene on the first call; later, widens the view whenever a body leaves the
  // framed box (never narrows it, so the camera does not breathe with the motion).
  void update_view(const Model& model, const State& state) {
    if (!framed) view.ground = choose_ground(model, state);
    const Aabb box = framing_box(model, state, view.ground);
    const bool inside = box.empty() || ((box.lo.array() >= framed_box.lo.array()).all() &&
                                        (box.hi.array() <= framed_box.hi.array()).all());
    if (framed && inside) return;
    if (!framed) framed_box = box;
    else framed_box.extend(box.lo), framed_box.extend(box.hi);
    frame(framed_box);
    framed = true;
  }

  void frame(const Aabb& box) {
    view.scene_centre = box.empty() ? Vec3::Zero() : Vec3(0.5 * (box.lo + box.hi));
    view.scene_radius = box.empty() ? 1.0 : std::max(0.5 * (box.hi - box.lo).norm(), 1e-3);
    const double aspect = double(options.width) / options.height;
    view.camera = box.empty() ? Camera{} : frame_box(box, view.ground.normal, options.orbit_deg, options.elevation_deg,
                                                     options.fov_y_deg, aspect);
    view.view_projection = view.camera.view_projection();
    view.width = options.width, view.height = options.height;
    // Light from the upper left, a little in front of the subject: lit faces look at the
    // camera and the shadow falls right and back, where the ground is visible.
    const Eigen::Vector3f up = view.ground.normal.cast<float>();
    const Eigen::Vector3f back = (view.camera.eye - view.camera.target).normalized();
    const Eigen::Vector3f right = up.cross(back).normalized();
    view.light = (1.0f * up - 0.5f * right + 0.6f * back).normalized();
  }

  void update_ground(const Model& model, const State& state) {
    if (!framed || view.ground.from_obstacle) return;
    const GroundPlane now = choose_ground(model, state);
    if ((now.point - view.ground.point).dot(view.ground.normal) < 0) view.ground.point = now.point;
  }

  void update_colors(const Model& model, const State& state) {
    vertex_values.assign(model.bodies.size(), {});
    if (options.color_map == ColorMapKind::None) return;
    const auto fields = compute_element_fields(model, state);
    const std::vector<double>& values = fields.at(color_map_field(options.color_map));
    scale = update_scale(options.color_map, values, have_scale ? &scale : nullptr);
    have_scale = true;
    for (size_t b = 0; b < model.bodies.size(); ++b)
      element_values_to_surface(model.bodies[b], values, vertex_values[b]);
  }
};

Renderer::Renderer(const RenderOptions& options) : m(std::make_unique<Impl>(options)) {}
Renderer::~Renderer() {
  try {
    m->context.make_current();  // GL objects must be deleted in the context that made them
  } catch (const RenderError&) {
    // Nothing better to do in a destructor; the context goes away with its objects anyway.
  }
}

void Renderer::reset_view() { m->framed = false; }

void Renderer::set_orbit(double orbit_deg, double elevation_deg) {
  m->options.orbit_deg = orbit_deg;
  m->options.elevation_deg = elevation_deg;
  m->framed = false;
}

void Renderer::draw(const Model& model, const State& state, const std::function<void()>& overlay) {
  m->context.make_current();
  m->update_ground(model, state);
  m->update_view(model, state);
  m->update_colors(model, state);
  m->surfaces.update(model, state, m->options.color_map, m->scale, m->vertex_values);
  if (m->options.wireframe) m->wireframe.update(model, state);

  m->framebuffer.bind_for_drawing();
  glClearStencil(0);
  glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);  // colour: the background covers it
  glDisable(GL_CULL_FACE);
  m->ground.draw_background();
  m->ground.draw_ground(m->view);
  if (m->options.shadow) m->surfaces.draw_shadows(m->view);
  m->surfaces.draw_surfaces(m->view);
  if (m->options.wireframe) m->wireframe.draw(m->view);
  m->legend_box = m->options.color_map == ColorMapKind::None
                      ? LegendBox{}
                      : m->legend.draw(m->options.color_map, m->scale, m->options.width, m->options.height);
  if (overlay) overlay();
  m->framebuffer.resolve();
}

void Renderer::read_rgb(uint8_t* dst) const {
  m->context.make_current();
  m->framebuffer.read_rgb(dst);
}

Image Renderer::image() const {
  Image image{m->options.width, m->options.height, {}};
  std::vector<uint8_t> bottom_up(3 * size_t(image.width) * image.height);
  read_rgb(bottom_up.data());
  image.rgb.resize(bottom_up.size());
  flip_rows(bottom_up.data(), image.rgb.data(), image.width, image.height);
  return image;
}

const RenderOptions& Renderer::options() const { return m->options; }
const Camera& Renderer::camera() const { return m->view.camera; }
Eigen::Vector3f Renderer::light_direction() const { return m->view.light; }
LegendBox Renderer::legend_box() const { return m->legend_box; }
std::string Renderer::description() const { return m->context.description(); }

}  // namespace sinew
