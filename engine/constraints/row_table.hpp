#pragma once
// Constraint rows: every kind of constraint (energy limit, strain limit, contact normal,
// friction) becomes rows of this one table, so the LCP solver never branches on kinds.
//
// Row i:  C_i(x) >= 0 (unilateral) or = 0 (bounded both ways), linearised as
//   C_i + h J_i (v - v_lin) >= 0, with J_i = dC_i/dx over a small stencil of nodes.
// Its multiplier lambda_i is a force along J_i, bounded lo_i <= lambda_i <= hi_i; a
// friction row's bounds are +-mu * lambda of its normal row, updated inside PGS.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

enum class RowKind { Energy, Strain, Contact, Friction, Attachment, Count };
constexpr int kRowKindCount = static_cast<int>(RowKind::Count);
const char* row_kind_name(RowKind kind);

struct RowTable {
  std::vector<RowKind> kind;
  std::vector<double> value;          // C_i at the linearisation point
  std::vector<double> lo, hi;         // multiplier bounds
  std::vector<int> normal_row;        // friction rows: their normal row; -1 otherwise
  std::vector<double> mu;             // friction rows: Coulomb coefficient
  std::vector<uint64_t> key;          // stable identity, for warm starts across steps
  // Curvature for SQP: -d2C_i/dx2 ~= curvature_i * R_e Ke R_e^T of element `element_i`
  // (energy limits); rows with element -1 are treated as linear (Gauss-Newton).
  std::vector<int> element;
  std::vector<double> curvature;
  // Or an explicit matrix over the element's first 12 coordinates (tet rows): index into
  // curvature_blocks, -1 for none.
  std::vector<int> curvature_block;
  std::vector<Eigen::Matrix<double, 12, 12>> curvature_blocks;
  std::vector<int> begin{0};          // rows + 1: stencil range in nodes / jac
  std::vector<int> nodes;             // global node per stencil entry
  std::vector<Vec3> jac;              // dC_i / dx_node per stencil entry
  std::vector<double> lambda;         // solution (force along J_i)
  long appended = 0;                  // rows added over the table's life: a work counter that
                                      // clear() keeps (StepWork::rows)

  int size() const { return static_cast<int>(kind.size()); }
  void clear();
  // Appends a row with an empty stencil; fill it with add_entry(). Returns its index.
  int add_row(RowKind k, double c, double lower, double upper, uint64_t identity);
  void add_entry(int node, const Vec3& d);  // to the last row
  // Appends every row of `other` after this table's own, as if added here (friction rows'
  // normal_row, stencils and curvature blocks re-indexed); `appended` counts them.
  void append(const RowTable& other);
  int count(RowKind k) const;
};

// Inline: the strain and contact builds add hundreds of rows and thousands of entries a build.
inline int RowTable::add_row(RowKind k, double c, double lower, double upper, uint64_t identity) {
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

inline void RowTable::add_entry(int node, const Vec3& d) {
  nodes.push_back(node);
  jac.push_back(d);
  begin.back() = static_cast<int>(nodes.size());
}

// A key from a kind and up to two indices (element, sub-row; vertex, obstacle...).
inline uint64_t row_key(RowKind k, uint32_t a, uint32_t b = 0) {
  return (uint64_t(k) << 60) ^ (uint64_t(a) << 24) ^ uint64_t(b);
}
// The parts of a row_key: its kind, its first index a and its second index b.
inline RowKind row_key_kind(uint64_t key) { return static_cast<RowKind>(key >> 60); }
inline uint64_t row_key_first(uint64_t key) { return (key >> 24) & ((uint64_t(1) << 36) - 1); }
inline uint32_t row_key_second(uint64_t key) { return static_cast<uint32_t>(key & 0xFFFFFF); }

}  // namespace sinew
