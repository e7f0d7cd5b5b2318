#include "engine/assembly/element_kernels.hpp"

namespace sinew {

int element_node_count(const Model& model, int e) {
  return model.element_type[e] == ElementType::Hex8 ? 8 : 4;
}

ElementNodes gather_element_positions(const Model& model, const VecX& x, int e) {
  ElementNodes out;
  out.count = element_node_count(model, e);
  const auto& nodes = model.element_nodes[e];
  for (int a = 0; a < 8; ++a) out.x[a] = a < out.count ? Vec3(x.segment<3>(3 * nodes[a])) : Vec3::Zero();
  return out;
}

ElementNodes gather_element_nodes(const Model& model, const VecX& x, int e) {
  ElementNodes out = gather_element_positions(model, x, e);
  const auto& nodes = model.element_nodes[e];
  for (int a = 0; a < 8; ++a) out.X[a] = a < out.count ? Vec3(model.rest_x.segment<3>(3 * nodes[a])) : Vec3::Zero();
  return out;
}

namespace {

std::array<Vec3, 4> first_four(const std::array<Vec3, 8>& p) { return {p[0], p[1], p[2], p[3]}; }

const Tet4Reference& tet_ref(const Model& model, int e) { return model.tet_references[model.element_reference[e]]; }
const Hex8Reference& hex_ref(const Model& model, int e) { return model.references[model.element_reference[e]]; }

}  // namespace

CorotatedElement compute_corotated_element(const Model& model, int e, const ElementNodes& nodes) {
  CorotatedElement out;
  if (model.element_type[e] == ElementType::Hex8) {
    out.R = compute_hex8_rotation(nodes.x, hex_ref(model, e).cell_size);
    out.u = hex8_corotated_displacement(out.R, nodes.x, nodes.X);
  } else {
    out.R = compute_tet4_rotation(tet_ref(model, e), first_four(nodes.x));
    out.u.setZero();
    out.u.head<12>() = tet4_corotated_displacement(out.R, first_four(nodes.x), first_four(nodes.X));
  }
  return out;
}

namespace {

// Ke U for U of 24 rows (a tet's Ke acts on the first 12; the rest of the product is 0).
template <int Columns>
Eigen::Matrix<double, 24, Columns> stiffness_times(const Model& model, int e, const Eigen::Matrix<double, 24, Columns>& u) {
  // lazyProduct: coefficient-based, vectorised kernels; Eigen's default for these sizes is
  // its general GEMM, whose packing cost more than the 24 x 24 x 2 product itself.
  if (model.element_type[e] == ElementType::Hex8) return hex_ref(model, e).Ke.lazyProduct(u);
  Eigen::Matrix<double, 24, Columns> out = Eigen::Matrix<double, 24, Columns>::Zero();
  out.template topRows<12>() = tet_ref(model, e).Ke.lazyProduct(u.template topRows<12>());
  return out;
}

}  // namespace

Vec24 element_stiffness_times(const Model& model, int e, const Vec24& u) { return stiffness_times<1>(model, e, u); }

Eigen::Matrix<double, 24, 2> element_stiffness_times(const Model& model, int e, const Eigen::Matrix<double, 24, 2>& u) {
  return stiffness_times<2>(model, e, u);
}

double element_limit_energy(const Model& model, int e, const Vec24& u) {
  return u.dot(element_stiffness_times(model, e, u));
}

Vec24 element_elastic_force(const Model& model, int e, const Mat3& R, const Vec24& u) {
  const Vec24 Ku = element_stiffness_times(model, e, u);
  Vec24 f = Vec24::Zero();
  for (int a = 0; a < element_node_count(model, e); ++a) f.segment<3>(3 * a) = -(R * Ku.segment<3>(3 * a));
  return f;
}

void element_warped_stiffness(const Model& model, int e, const Mat3& R, Mat24& out) {
  if (model.element_type[e] == ElementType::Hex8) {
    hex8_warped_stiffness(hex_ref(model, e), R, out);
    return;
  }
  Mat12 K;
  tet4_warped_stiffness(tet_ref(model, e), R, K);
  out.setZero();
  out.topLeftCorner<12, 12>() = K;
}

double element_rest_volume(const Model& model, int e) {
  if (model.element_type[e] == ElementType::Hex8) return std::pow(hex_ref(model, e).cell_size, 3);
  return tet_ref(model, e).volume;
}

Mat3 element_center_deformation_gradient(const Model& model, int e, const ElementNodes& nodes) {
  if (model.element_type[e] == ElementType::Hex8)
    return hex8_deformation_gradient(hex_ref(model, e), nodes.x, Vec3::Zero());
  return tet4_deformation_gradient(tet_ref(model, e), first_four(nodes.x));
}

ElementQuadrature element_quadrature(const Model& model, int e) {
  if (model.element_type[e] == ElementType::Hex8) {
    const Hex8Reference& ref = hex_ref(model, e);
    return {8, ref.dN_dX.data(), ref.det_dXds, model.bodies[model.element_body[e]].material.mean_dilatation};
  }
  const int reference = model.element_reference[e];
  return {1, &model.tet_gradients[reference], model.tet_volumes[reference]};
}

}  // namespace sinew
