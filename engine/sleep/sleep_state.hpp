#pragma once
// Which bodies sleep (issue 7, section 3) and what is kept to notice when one must wake.
// Written by World::step through engine/sleep/sleep.hpp; per-body vectors are sized by the
// World's constructor.
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

struct SleepState {
  std::vector<char> asleep;      // per body: 1 while asleep (its x kept, v = 0)
  std::vector<int> quiet_steps;  // per body: consecutive steps it ended quiet (awake bodies)
  std::vector<int> island;       // per body, while asleep: the lowest body of the island it fell
                                 // asleep with (bodies linked by rows wake together); -1 awake
  std::vector<Aabb> bounds;      // per body, while asleep: its surface bounds (a moving obstacle
                                 // coming within the contact margin wakes it)
  VecX external_force;           // State::external_force when a body last fell asleep
  bool changed = false;          // the sleeping set changed since the stages' model was made

  int count() const {
    int n = 0;
    for (char a : asleep) n += a;
    return n;
  }
  bool all() const { return !asleep.empty() && count() == static_cast<int>(asleep.size()); }
};

}  // namespace sinew
