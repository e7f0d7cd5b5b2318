#pragma once
// Sleeping bodies (issue 7, section 3). A body whose RMS speed and RMS acceleration (net
// force per unit mass) stay under solver.sleep_speed / sleep_acceleration for
// solver.sleep_steps steps sleeps, together with every body its constraint rows link it to
// (an island), unless something is about to move it. A sleeping body keeps x, has v = 0 and
// costs no element, row or solver work; it wakes, with its island, when a row of an awake
// body touches it, an obstacle moves within the contact margin of it, a load on it ramps,
// a driven node of it moves, its external force changes, a caller gives it a velocity or
// holds one of its vertices (State::attachments: a grab).
// World::step calls wake_disturbed_bodies before the stages and update_sleep after them;
// the stages see freeze_sleeping_bodies' model while some bodies sleep, and nothing runs
// while all do. docs/ARCHITECTURE.md, "Sleeping bodies", has the whole design.
#include "engine/model.hpp"
#include "engine/state.hpp"

namespace sinew {

// The model the stages see while the bodies marked in `asleep` sleep: their nodes are not
// unknowns (free_index -1, like fixed nodes: the solve gives them v = 0), their elements
// leave the colours (no assembly, no Newton), their energy and strain limits are off (no
// rows: x cannot change, so they cannot become violated), their driven nodes are dropped and
// body_asleep spares them obstacle contact; awake bodies still collide with their surfaces,
// as with fixed ones. The system pattern is rebuilt over the remaining unknowns.
Model freeze_sleeping_bodies(const Model& model, const std::vector<char>& asleep);

// True if something outside body b will move it during [t, t + h]: a scene load on it still
// ramping, a driven node of it still moving, or an obstacle that moves and ends the step
// within the contact margin of `bounds` (the body's surface bounds).
bool body_disturbed(const Model& model, int b, double t, const Aabb& bounds);

// Before a step: wakes (with their islands) the sleeping bodies that body_disturbed, an
// external force other than when they fell asleep or a non-zero velocity would move.
void wake_disturbed_bodies(const Model& model, State& state);

// After a successful step (state.t at its end), given the velocities at its start: wakes
// the sleepers that the step's rows touch, counts quiet steps of the bodies that were awake
// and puts to sleep each island of them that has been quiet for sleep_steps steps and is
// not disturbed (its nodes get v = 0).
void update_sleep(const Model& model, const VecX& v0, State& state);

// Wakes every sleeping body of b's island.
void wake_island(SleepState& sleep, int b);

}  // namespace sinew
