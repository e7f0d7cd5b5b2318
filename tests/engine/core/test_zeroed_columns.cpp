// ZeroedColumns: a sparse right-hand side's storage is all zero again after each use, so
// the next view, whatever its shape, starts from zeros without being zeroed.
#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "engine/core/zeroed_columns.hpp"

using namespace sinew;

TEST_CASE("zeroed_columns: set and added entries are cleared, and a view of another shape is all zero") {
  ZeroedColumns columns;
  {
    Eigen::Map<MatX> B = columns.view(6, 4);
    CHECK(B.isZero(0));
    const ZeroedColumns::ClearOnExit clear{columns};
    columns.set(B, 5, 3, 2.0);
    columns.add(B, 1, 0, 0.5);
    columns.add(B, 1, 0, 0.25);  // twice on one entry
    CHECK(B(5, 3) == 2.0);
    CHECK(B(1, 0) == 0.75);
    CHECK(B.cwiseAbs().sum() == 2.75);
  }
  CHECK(columns.view(6, 4).isZero(0));
  CHECK(columns.view(4, 6).isZero(0));  // the same storage, another layout
  CHECK(columns.view(10, 5).isZero(0));  // grown: new storage is zero too
}

TEST_CASE("zeroed_columns: a scope left by an exception clears what it set") {
  ZeroedColumns columns;
  try {
    Eigen::Map<MatX> B = columns.view(3, 3);
    const ZeroedColumns::ClearOnExit clear{columns};
    columns.set(B, 2, 2, 1.0);
    throw std::runtime_error("solve failed");
  } catch (const std::runtime_error&) {
  }
  CHECK(columns.view(3, 3).isZero(0));
}

TEST_CASE("zeroed_columns: the pattern lists each column's recorded rows, in any recording order") {
  ZeroedColumns columns;
  Eigen::Map<MatX> B = columns.view(5, 4);
  const ZeroedColumns::ClearOnExit clear{columns};
  columns.set(B, 4, 2, 1.0);
  columns.set(B, 0, 0, 1.0);
  columns.add(B, 3, 2, 1.0);
  columns.add(B, 3, 2, 1.0);  // the same entry twice: listed twice
  // column 1 and column 3: nothing recorded
  const ZeroedColumns::Pattern& p = columns.pattern(4);
  CHECK(p.start == std::vector<int>{0, 1, 1, 4, 4});
  CHECK(p.rows[0] == 0);
  std::vector<int> column2(p.rows.begin() + 1, p.rows.begin() + 4);
  std::sort(column2.begin(), column2.end());
  CHECK(column2 == std::vector<int>{3, 3, 4});
  CHECK_THROWS_AS(columns.pattern(2), std::logic_error);  // column 2 is beyond two columns
}
