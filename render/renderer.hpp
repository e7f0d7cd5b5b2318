#pragma once
// Draws a simulation off-screen: background, ground grid with the bodies' shadows, lit
// embedded surfaces (optionally colour-mapped, with a legend), optional lattice wireframe.
// Reads a const Model / State; owns its EGL context, so every call must come from the thread
// that constructed it.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "engine/world.hpp"
#include "render/camera.hpp"
#include "render/color_map.hpp"
#include "render/image.hpp"
#include "render/legend_box.hpp"

namespace sinew {

struct RenderOptions {
  int width = 1280, height = 720;
  int samples = 4;                 // MSAA samples (clamped to what the driver offers)
  bool wireframe = false;          // the simulation lattice
  bool shadow = true;              // the bodies' shadow on the ground
  ColorMapKind color_map = ColorMapKind::None;
  double orbit_deg = 30;           // camera azimuth around the up axis
  double elevation_deg = 20;       // camera height above the horizon
  double fov_y_deg = 40;
};

class Renderer {
 public:
  // Creates the context and GL resources; throws RenderError (no EGL display, bad size).
  explicit Renderer(const RenderOptions& options);
  ~Renderer();

  // Draws one frame. The first call (and the first after reset_view()) frames the bodies;
  // later the view only widens, when a body leaves what is framed, so motion stays visible
  // against a still background. The ground is the scene's plane obstacle, else the lowest
  // surface point seen so far (it only ever moves down).
  // `overlay`, if given, runs after the scene with this renderer's context current and its
  // framebuffer bound (the ImGui panel of ui/ draws itself there, so it is in the capture).
  void draw(const Model& model, const State& state, const std::function<void()>& overlay = {});
  void draw(const World& world) { draw(world.model(), world.state()); }
  void reset_view();
  // Moves the camera to a new azimuth and elevation (degrees) and frames the bodies anew.
  void set_orbit(double orbit_deg, double elevation_deg);

  // The last frame, tightly packed RGB, bottom row first (as GL stores it).
  void read_rgb(uint8_t* dst) const;
  // The last frame as an image (top row first).
  Image image() const;

  const RenderOptions& options() const;
  const Camera& camera() const;
  // Unit vector towards the directional light (it also casts the shadow), set with the camera.
  Eigen::Vector3f light_direction() const;
  // Where the legend went in the last frame (empty without a colour map).
  LegendBox legend_box() const;
  std::string description() const;  // platform, GL version and renderer

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace sinew
