#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "engine/materials/material.hpp"

using namespace sinew;

TEST_CASE("make_material builds every listed material under its own name") {
  MaterialParameters p;
  p.young = 1e5;
  p.poisson = 0.3;
  CHECK(material_names().size() == 7);
  for (const std::string& name : material_names()) {
    const auto m = make_material(name, p);
    REQUIRE(m != nullptr);
    CHECK(std::string(m->name()) == name);
    CHECK(m->is_defined(Mat3::Identity()));
  }
}

TEST_CASE("make_material rejects an unknown name, listing the known ones") {
  MaterialParameters p;
  p.young = 1e5;
  p.poisson = 0.3;
  try {
    make_material("rubber", p);
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.find("rubber") != std::string::npos);
    for (const std::string& name : material_names()) CHECK(message.find(name) != std::string::npos);
  }
}

TEST_CASE("Lame parameters from E and nu, and invalid parameters rejected") {
  MaterialParameters p;
  p.young = 2.6e5;
  p.poisson = 0.3;
  const LameParameters lame = lame_parameters(p);
  CHECK(lame.mu == doctest::Approx(1e5));          // E / (2 (1 + nu))
  CHECK(lame.lambda == doctest::Approx(1.5e5));    // E nu / ((1 + nu)(1 - 2 nu))
  p.poisson = 0.5;
  CHECK_THROWS_AS(lame_parameters(p), std::invalid_argument);
  p.poisson = 0.3;
  p.young = 0;
  CHECK_THROWS_AS(make_material("stable_neo_hookean", p), std::invalid_argument);
}
