#pragma once
// Projected tet Hessians kept from one Newton assembly to the next (solver.hessian_reuse_tolerance):
// a one-point tet of an invariant material whose F has moved by at most the tolerance
// (entrywise) since its Hessian was formed keeps that Hessian, and skips its SVD, eigensystem
// and 12 x 12 blocks. The kept blocks' sum lives in `values` (the system pattern's values,
// times h^2), updated by each re-formed tet's change (new blocks less its kept ones), so a
// pass costs only the tets that moved. A resting or falling body's Hessian pass then costs
// little more than its gradient pass.
#include <array>
#include <vector>

#include "engine/core/types.hpp"

namespace sinew {

struct KeptTetHessians {
  double coeff = 0;        // the h^2 the blocks were formed with (another h drops them all)
  int entries = -1;        // the pattern's entry count they were scattered into
  std::vector<Mat3> F;     // per element: the F its blocks were formed at
  std::vector<char> kept;  // per element: blocks held (a one-point invariant tet that was re-formed once)
  std::vector<std::array<double, 144>> blocks;  // per element: coeff K, 16 3 x 3 blocks column by column
  std::vector<double> values;  // sum of the held blocks at the system pattern's positions
  // Set by each pass: per element, whether this pass formed its blocks afresh.
  std::vector<char> fresh;
  long formed = 0;         // tets formed afresh by the last pass (the rest kept theirs)
  // Whether every hyperelastic element is such a tet, and whether any is (-1: not yet known;
  // reset with the rest): with every one a pass writes the hyperelastic part of the values
  // whole (hyperelastic_derivatives); with none the store is not used.
  int every_element_kept = -1, any_element_kept = -1;

  // Sized for `elements` tets and `entries` values at coefficient `h2`; drops everything held
  // unless those match what it holds.
  void prepare(int elements, int entries, double h2);
  void clear();  // drops everything (a new pattern: another awake set)
  // The blocks and the sum, once some element keeps its Hessian (a model without such tets
  // holds neither: 1,152 bytes an element).
  void allocate_blocks();
  // Whether a tet at F must be formed afresh (none held, or F moved past the tolerance).
  bool needs_forming(int e, const Mat3& F, double tolerance) const;
  // Tet e's blocks become `formed` (coeff K laid out as `blocks`), formed at F: values gains
  // formed - held at the tet's 48 scatter positions `at` (SystemPattern::element_scatter; a
  // negative one, a fixed node's, is skipped). True when the held blocks were far larger
  // (a transient near a degenerate F: neo-Hookean's volume terms reach ~1e13 of a normal
  // entry): values then hold their round-off, ~u of them, and want summing anew (rebuild).
  bool replace(int e, const Mat3& at_F, const std::array<double, 144>& formed, const int* at);
  // values summed anew from the held blocks, element by element in index order (the same
  // for any thread count), at the system pattern's scatter positions (element e's from
  // element_scatter[scatter_begin[e]]).
  void rebuild(const std::vector<int>& element_scatter, const std::vector<int>& scatter_begin);
};

}  // namespace sinew
