// RowTable::append: rows built in a table of their own and appended are the rows built in
// place after the others (friction rows' normal_row, stencils and curvature blocks
// re-indexed), which lets build_rows build kinds side by side.
#include <doctest/doctest.h>

#include "engine/constraints/row_table.hpp"

using namespace sinew;

namespace {

// An energy row on 3 nodes and a strain row with a curvature block.
void add_limit_rows(RowTable& rows) {
  const int energy = rows.add_row(RowKind::Energy, 0.1, 0, 1e300, row_key(RowKind::Energy, 4));
  rows.element[energy] = 4;
  rows.curvature[energy] = 0.5;
  for (int n = 0; n < 3; ++n) rows.add_entry(n, Vec3(n, 1, 2));
  const int strain = rows.add_row(RowKind::Strain, -0.2, 0, 1e300, row_key(RowKind::Strain, 7, 3));
  rows.element[strain] = 7;
  rows.curvature_block[strain] = static_cast<int>(rows.curvature_blocks.size());
  rows.curvature_blocks.push_back(Eigen::Matrix<double, 12, 12>::Identity());
  rows.add_entry(5, Vec3(1, 0, 0));
}

// A contact row and its two friction rows, each on 2 nodes, and a second curvature block.
void add_contact_and_friction(RowTable& rows) {
  const int normal = rows.add_row(RowKind::Contact, 0.01, 0, 1e300, row_key(RowKind::Contact, 9));
  rows.add_entry(8, Vec3(0, 1, 0));
  rows.add_entry(9, Vec3(0, 2, 0));
  for (int j = 0; j < 2; ++j) {
    const int f = rows.add_row(RowKind::Friction, 0.001 * j, -1e300, 1e300, row_key(RowKind::Friction, 9, j));
    rows.normal_row[f] = normal;
    rows.mu[f] = 0.4;
    rows.lambda[f] = 3.0 + j;
    rows.add_entry(8, Vec3(1, 0, j));
    rows.add_entry(9, Vec3(2, 0, j));
  }
  rows.curvature_block[normal] = static_cast<int>(rows.curvature_blocks.size());
  rows.curvature_blocks.push_back(2 * Eigen::Matrix<double, 12, 12>::Identity());
}

}  // namespace

TEST_CASE("row_table: appending a table equals adding its rows in place") {
  RowTable in_place;
  add_limit_rows(in_place);
  add_contact_and_friction(in_place);

  RowTable appended, contacts;
  add_limit_rows(appended);
  add_contact_and_friction(contacts);
  const long before = appended.appended;
  appended.append(contacts);

  REQUIRE(appended.size() == 5);
  CHECK(appended.appended == before + 3);
  CHECK(appended.kind == in_place.kind);
  CHECK(appended.value == in_place.value);
  CHECK(appended.lo == in_place.lo);
  CHECK(appended.hi == in_place.hi);
  CHECK(appended.normal_row == in_place.normal_row);
  CHECK(appended.normal_row[3] == 2);  // friction rows point at their contact row, now row 2
  CHECK(appended.mu == in_place.mu);
  CHECK(appended.key == in_place.key);
  CHECK(appended.element == in_place.element);
  CHECK(appended.curvature == in_place.curvature);
  CHECK(appended.curvature_block == in_place.curvature_block);
  CHECK(appended.curvature_block[2] == 1);  // the contact row's block follows the strain row's
  REQUIRE(appended.curvature_blocks.size() == in_place.curvature_blocks.size());
  for (size_t b = 0; b < in_place.curvature_blocks.size(); ++b) CHECK(appended.curvature_blocks[b] == in_place.curvature_blocks[b]);
  CHECK(appended.begin == in_place.begin);
  CHECK(appended.nodes == in_place.nodes);
  CHECK(appended.jac == in_place.jac);
  CHECK(appended.lambda == in_place.lambda);

  // An empty table appends nothing; appending to an empty table copies.
  RowTable empty, copy;
  appended.append(empty);
  CHECK(appended.size() == 5);
  CHECK(appended.begin.size() == 6);
  copy.append(contacts);
  CHECK(copy.begin == contacts.begin);
  CHECK(copy.normal_row == contacts.normal_row);
}
