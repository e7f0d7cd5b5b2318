#pragma once
// A surface point held at a target: the grab of an interactive session (ui/), solved with
// the other constraints instead of as a stiff spring, so the point follows the cursor to
// the SQP tolerance with no stiffness to tune and no stability limit on h. Three
// bilateral rows per attachment, C_j = (p - target) . e_j = 0, p = sum_n w_n x_n the
// embedded vertex (weights of its cell), multipliers unbounded both ways.
#include <cstdint>
#include <vector>

#include "engine/constraints/row_table.hpp"
#include "engine/model.hpp"

namespace sinew {

struct Attachment {
  int body = 0;
  int vertex = 0;                // surface vertex of the body
  Vec3 target = Vec3::Zero();    // m, where the vertex is held at the end of the step
};

// Appends the rows; returns the largest |p - target| (m) over the attachments at x.
double add_attachment_rows(const Model& model, const std::vector<Attachment>& attachments, const VecX& x,
                           RowTable& rows);

// The embedded position of a body's surface vertex at x.
Vec3 attached_point(const Model& model, const Attachment& attachment, const VecX& x);

}  // namespace sinew
