// With every awake body hyperelastic, stage 1 writes A0's diagonal alone (the mass and mass
// damping) and leaves the system's other values as they were (assemble_system_matrix):
// Newton reads that diagonal and nothing else of A0. Checked by filling the whole matrix with
// NaN before each step of one of two lockstep runs: the states stay the same bit for bit.
#include <doctest/doctest.h>

#include <limits>
#include <string>

#include "tests/engine/step/snh_landing_box.hpp"

using namespace sinew;

TEST_CASE("Newton never reads A0's values off its diagonal when every awake body is hyperelastic") {
  for (const char* solver : {"\"newton_max_iterations\": 1, \"refactor_interval\": 8",
                             "\"newton_max_iterations\": 30, \"refactor_interval\": 1",
                             // every Hessian formed: H takes A0's pattern and diagonal, not the kept sum
                             "\"newton_max_iterations\": 1, \"hessian_reuse_tolerance\": 0"}) {
    CAPTURE(solver);
    const std::string fields = std::string(solver) + ", \"sleep_steps\": 0";
    World clean = test::snh_landing_box(fields), poisoned = test::snh_landing_box(fields);
    for (int step = 0; step < 40; ++step) {
      SparseMatrix& system = poisoned.mutable_state().system;
      std::fill_n(system.valuePtr(), system.nonZeros(), std::numeric_limits<double>::quiet_NaN());
      REQUIRE(clean.step());
      REQUIRE(poisoned.step());
      CAPTURE(step);
      REQUIRE(poisoned.state().x == clean.state().x);
      REQUIRE(poisoned.state().v == clean.state().v);
    }
  }
}
