// Up direction, ground placement and the framed box.
#include <doctest/doctest.h>

#include "render/scene_layout.hpp"

using namespace sinew;

namespace {

// A model with no bodies and a state whose "surface" is the given points (one body).
struct Fixture {
  Model model;
  State state;
  explicit Fixture(std::vector<Vec3> points) {
    model.bodies.resize(1);
    model.gravity = Vec3(0, -9.81, 0);
    state.surface = {std::move(points)};
  }
};

}  // namespace

TEST_CASE("layout: up is the plane obstacle's normal, else against gravity, else +y") {
  Fixture f({{0, 0, 0}});
  CHECK(scene_up(f.model).isApprox(Vec3::UnitY()));
  f.model.gravity = Vec3(0, 0, -2);
  CHECK(scene_up(f.model).isApprox(Vec3::UnitZ()));
  f.model.gravity.setZero();
  CHECK(scene_up(f.model).isApprox(Vec3::UnitY()));
  ObstacleDesc plane;
  plane.normal = Vec3(1, 0, 0);
  f.model.obstacles.push_back(plane);
  CHECK(scene_up(f.model).isApprox(Vec3::UnitX()));
}

TEST_CASE("layout: the ground is the plane obstacle, else through the lowest surface point") {
  Fixture f({{0, 2, 0}, {1, 0.5, 0}, {0, 3, 1}});
  GroundPlane g = choose_ground(f.model, f.state);
  CHECK(!g.from_obstacle);
  CHECK(g.point.y() == doctest::Approx(0.5));
  CHECK(g.normal.isApprox(Vec3::UnitY()));
  ObstacleDesc plane;
  plane.point = Vec3(0, -1, 0);
  f.model.obstacles.push_back(plane);
  g = choose_ground(f.model, f.state);
  CHECK(g.from_obstacle);
  CHECK(g.point.y() == doctest::Approx(-1));
}

TEST_CASE("layout: the framed box takes in the bodies' footprint on a near ground, not on a far one") {
  Fixture f({{0, 1, 0}, {1, 2, 1}});
  GroundPlane near{Vec3(0, 0, 0), Vec3::UnitY(), true};
  Aabb box = framing_box(f.model, f.state, near);
  CHECK(box.lo.y() == doctest::Approx(0));
  CHECK(box.hi.y() == doctest::Approx(2));
  GroundPlane far{Vec3(0, -100, 0), Vec3::UnitY(), true};
  box = framing_box(f.model, f.state, far);
  CHECK(box.lo.y() == doctest::Approx(1));
  const Aabb bodies = surface_bounds(f.model, f.state);
  CHECK(bodies.lo.isApprox(Vec3(0, 1, 0)));
  CHECK(bodies.hi.isApprox(Vec3(1, 2, 1)));
}
