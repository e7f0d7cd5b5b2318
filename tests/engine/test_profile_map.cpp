// ProfileMap (engine/profile_map.hpp): reads like the std::map it replaced in StepProfile,
// and clear() keeps its entries' storage (a warm step allocates nothing).
#include <doctest/doctest.h>

#include <map>
#include <stdexcept>
#include <string>

#include "engine/profile.hpp"

using namespace sinew;

TEST_CASE("profile map: sorted, present entries only, like std::map") {
  ProfileMap<int> map;
  std::map<std::string, int> reference;
  for (const char* name : {"sqp", "pgs", "newton", "pgs"}) {
    map[name] += 2;
    reference[name] += 2;
  }
  CHECK(map.size() == reference.size());
  auto it = reference.begin();
  for (const auto& [name, value] : map) {
    REQUIRE(it != reference.end());
    CHECK(name == it->first);
    CHECK(value == it->second);
    ++it;
  }
  CHECK(map.count("pgs") == 1);
  CHECK(map.at("pgs") == 4);
  CHECK(map.find("sqp") != map.end());
  CHECK_THROWS_AS(map.at("pcg"), std::out_of_range);
}

TEST_CASE("profile map: clear() hides entries, which come back at zero") {
  ProfileMap<double> map;
  map["strain"] = 0.5;
  map.clear();
  CHECK(map.empty());
  CHECK(map.count("strain") == 0);
  CHECK(map["strain"] == 0.0);  // value-initialised again, not the old 0.5
  CHECK(map.size() == 1);
}

TEST_CASE("profile map: a StepProfile copies and assigns") {
  StepProfile a, b;
  a.iterations["sqp"] = 3;
  a.violation["strain"] = 1e-4;
  b.iterations["pgs"] = 7;
  b = a;  // StepProfile, State and World stay copy-assignable
  CHECK(b.iterations == a.iterations);
  CHECK(b.iterations.count("pgs") == 0);
  const StepProfile c(a);
  CHECK(c.violation.at("strain") == 1e-4);
}
