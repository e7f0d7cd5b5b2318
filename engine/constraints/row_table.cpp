#include "engine/constraints/row_table.hpp"

#include <algorithm>

namespace sinew {

const char* row_kind_name(RowKind kind) {
  static const char* names[] = {"energy", "strain", "contact", "friction", "attachment"};
  return names[static_cast<int>(kind)];
}

void RowTable::clear() {
  kind.clear(), value.clear(), lo.clear(), hi.clear(), normal_row.clear(), mu.clear();
  key.clear(), element.clear(), curvature.clear(), nodes.clear(), jac.clear(), lambda.clear();
  curvature_block.clear(), curvature_blocks.clear();
  begin.assign(1, 0);
}

int RowTable::add_row(RowKind k, double c, double lower, double upper, uint64_t identity) {
  ++appended;
  kind.push_back(k);
  value.push_back(c);
  lo.push_back(lower);
  hi.push_back(upper);
  normal_row.push_back(-1);
  mu.push_back(0);
  key.push_back(identity);
  element.push_back(-1);
  curvature.push_back(0);
  curvature_block.push_back(-1);
  lambda.push_back(0);
  begin.push_back(static_cast<int>(nodes.size()));
  return size() - 1;
}

void RowTable::add_entry(int node, const Vec3& d) {
  nodes.push_back(node);
  jac.push_back(d);
  begin.back() = static_cast<int>(nodes.size());
}

int RowTable::count(RowKind k) const { return static_cast<int>(std::count(kind.begin(), kind.end(), k)); }

}  // namespace sinew
