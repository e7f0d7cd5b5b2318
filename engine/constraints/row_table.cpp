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

void RowTable::append(const RowTable& other) {
  const int row_base = size(), entry_base = static_cast<int>(nodes.size());
  const int block_base = static_cast<int>(curvature_blocks.size());
  appended += other.size();
  kind.insert(kind.end(), other.kind.begin(), other.kind.end());
  value.insert(value.end(), other.value.begin(), other.value.end());
  lo.insert(lo.end(), other.lo.begin(), other.lo.end());
  hi.insert(hi.end(), other.hi.begin(), other.hi.end());
  for (const int r : other.normal_row) normal_row.push_back(r >= 0 ? r + row_base : -1);
  mu.insert(mu.end(), other.mu.begin(), other.mu.end());
  key.insert(key.end(), other.key.begin(), other.key.end());
  element.insert(element.end(), other.element.begin(), other.element.end());
  curvature.insert(curvature.end(), other.curvature.begin(), other.curvature.end());
  for (const int b : other.curvature_block) curvature_block.push_back(b >= 0 ? b + block_base : -1);
  curvature_blocks.insert(curvature_blocks.end(), other.curvature_blocks.begin(), other.curvature_blocks.end());
  for (int i = 1; i < static_cast<int>(other.begin.size()); ++i) begin.push_back(other.begin[i] + entry_base);
  nodes.insert(nodes.end(), other.nodes.begin(), other.nodes.end());
  jac.insert(jac.end(), other.jac.begin(), other.jac.end());
  lambda.insert(lambda.end(), other.lambda.begin(), other.lambda.end());
}

int RowTable::count(RowKind k) const { return static_cast<int>(std::count(kind.begin(), kind.end(), k)); }

}  // namespace sinew
