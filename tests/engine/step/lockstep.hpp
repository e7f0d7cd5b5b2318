#pragma once
// Shared by the lockstep tests (test_sqp_conjugate_steps.cpp, test_sqp_shared_solve.cpp):
// two worlds of one scene with one solver setting apart, the second taking the first's
// state before every step, so that both solve the same problem; a step compares only while
// both hold the same factorisation.
#include <algorithm>

#include "engine/world.hpp"

namespace sinew::test {

// The step's count of an iteration or event (0 when not reported).
inline long step_count_of(const World& w, const char* key) {
  const auto& it = w.profile().iterations;
  return it.count(key) ? it.at(key) : 0L;
}

// Whether the step made its scheduled factorisation.
inline bool factorised_this_step(const World& w) {
  return w.profile().skipped[static_cast<int>(Stage::Factorize)].empty();
}

// Whether the two worlds hold the same factorisation after this step, given whether they
// did before it: from a scheduled factorisation (made by both from the same state) until
// either refactorises at a stall.
inline bool same_factorisation(bool before, const World& a, const World& b) {
  return (before || (factorised_this_step(a) && factorised_this_step(b))) &&
         step_count_of(a, "sqp_refactorisations") == 0 && step_count_of(b, "sqp_refactorisations") == 0;
}

// The largest distance between a node's positions in x and y.
inline double farthest_node(const VecX& x, const VecX& y) {
  double farthest = 0;
  for (Eigen::Index n = 0; n < x.size() / 3; ++n) farthest = std::max(farthest, (x.segment<3>(3 * n) - y.segment<3>(3 * n)).norm());
  return farthest;
}

}  // namespace sinew::test
