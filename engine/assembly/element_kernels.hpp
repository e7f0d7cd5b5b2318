#pragma once
// Per-element math of the linear corotational element, for hex8 and tet4 alike. Results are
// padded to 8 nodes (24 entries): a tet fills the first 12 and leaves zeros, matching its
// element_nodes (4 nodes, then -1). Stages call these instead of hex8_* / tet4_* directly,
// so that every stage handles both element types through one code path.
#include "engine/model.hpp"

namespace sinew {

int element_node_count(const Model& model, int e);

// Node positions of element e gathered from x (3 * nodes) and from the rest positions.
struct ElementNodes {
  int count = 8;
  std::array<Vec3, 8> x, X;  // unused entries are zero
};
ElementNodes gather_element_nodes(const Model& model, const VecX& x, int e);
// The current positions alone (x; X left unset): the hyperelastic passes read no rest
// position (their shape gradients are the model's), and gathering X took a fifth of the
// stores and a second scattered read per node there.
ElementNodes gather_element_positions(const Model& model, const VecX& x, int e);

// Rotation R (hex8: innermost tet, paper 000; tet4: polar part of F) and the corotated
// displacement u = R^T x - X.
struct CorotatedElement {
  Mat3 R;
  Vec24 u;
};
CorotatedElement compute_corotated_element(const Model& model, int e, const ElementNodes& nodes);

Vec24 element_stiffness_times(const Model& model, int e, const Vec24& u);    // Ke u
Eigen::Matrix<double, 24, 2> element_stiffness_times(const Model& model, int e,
                                                    const Eigen::Matrix<double, 24, 2>& u);  // Ke [u1 u2]
double element_limit_energy(const Model& model, int e, const Vec24& u);      // Ue = u^T Ke u
Vec24 element_elastic_force(const Model& model, int e, const Mat3& R, const Vec24& u);  // -R Ke u
void element_warped_stiffness(const Model& model, int e, const Mat3& R, Mat24& out);    // R Ke R^T
double element_rest_volume(const Model& model, int e);
// F at the element centre (tet4: its constant F).
Mat3 element_center_deformation_gradient(const Model& model, int e, const ElementNodes& nodes);

// Quadrature of element e for the hyperelastic path: per point, shape-function gradients
// dN/dX (rows: nodes, padded with zero rows) and the volume weight.
struct ElementQuadrature {
  int points = 0;
  const Mat83* dN_dX = nullptr;  // `points` matrices
  double weight = 0;             // the same for every point
  // The volume term at the element's mean J (material "volume_term": "mean_dilatation",
  // hex8 only): mean_dilatation_element.hpp.
  bool mean_dilatation = false;
};
ElementQuadrature element_quadrature(const Model& model, int e);

}  // namespace sinew
