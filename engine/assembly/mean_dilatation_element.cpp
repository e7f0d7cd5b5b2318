#include "engine/assembly/mean_dilatation_element.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "engine/assembly/hyperelastic_element.hpp"

namespace sinew {
namespace {

constexpr int kMaxPoints = 8;

struct PointState {
  Mat3 F;
  double Ic = 0;
  double J = 0;
};

// F, Ic and J at each point, and Jbar.
double gather_points(const ElementQuadrature& quad, const ElementNodes& nodes, PointState* points) {
  double volume = 0, mean_J = 0;
  for (int q = 0; q < quad.points; ++q) {
    const Mat3 F = deformation_gradient(quad.dN_dX[q], nodes);
    points[q] = {F, F.squaredNorm(), F.determinant()};
    volume += quad.weight;
    mean_J += quad.weight * points[q].J;
  }
  return mean_J / volume;
}

// B_q^T vec(M): the nodal vector of a per-point 3x3 stress-like matrix.
void add_nodal(const Mat83& dN, int n, const Mat3& M, double w, Vec24& out) {
  for (int a = 0; a < n; ++a) out.segment<3>(3 * a) += w * (M * dN.row(a).transpose());
}

}  // namespace

// The weights sum to V, so sum_q w psi(Ic_q, Jbar) = sum_q w f(Ic_q) + V g(Jbar): the
// energy needs no split of psi into f and g.
double mean_dilatation_element_energy(const InvariantMaterial& material, const ElementQuadrature& quad,
                                      const ElementNodes& nodes) {
  assert(quad.points > 0 && quad.points <= kMaxPoints);
  PointState points[kMaxPoints];
  const double mean_J = gather_points(quad, nodes, points);
  double energy = 0;
  for (int q = 0; q < quad.points; ++q) {
    const double psi = material.terms(points[q].Ic, mean_J).psi;
    if (!std::isfinite(psi)) return std::numeric_limits<double>::infinity();
    energy += quad.weight * psi;
  }
  return energy;
}

double mean_dilatation_element_derivatives(const InvariantMaterial& material, const ElementQuadrature& quad,
                                           const ElementNodes& nodes, bool exact, Vec24& gradient,
                                           Mat24* hessian) {
  assert(quad.points > 0 && quad.points <= kMaxPoints);
  PointState points[kMaxPoints];
  const double mean_J = gather_points(quad, nodes, points);
  const int n = nodes.count;
  const double volume = quad.points * quad.weight;
  gradient.setZero();
  if (hessian) hessian->setZero();
  Vec24 b = Vec24::Zero();  // sum_q w B_q^T vec(cof F_q) = V dJbar/dx
  double energy = 0;
  InvariantTerms t;
  for (int q = 0; q < quad.points; ++q) {
    const PointState& p = points[q];
    t = material.terms(p.Ic, mean_J);
    energy += quad.weight * t.psi;
    const Mat3 cof = cofactor_matrix(p.F);
    add_nodal(quad.dN_dX[q], n, 2 * t.f1 * p.F + t.g1 * cof, quad.weight, gradient);
    add_nodal(quad.dN_dX[q], n, cof, quad.weight, b);
    if (!hessian) continue;
    InvariantTerms point_terms = t;
    point_terms.g2 = 0;  // the volume curvature is the element's (the rank-one term below)
    Mat9 D = invariant_hessian(p.F, point_terms);
    if (!exact) D = remove_negative_modes(D, invariant_eigensystem(p.F, point_terms));
    add_point_hessian(quad.dN_dX[q], n, D, quad.weight, *hessian);
  }
  if (!std::isfinite(energy)) energy = std::numeric_limits<double>::infinity();
  if (hessian) {
    const double g2 = exact ? t.g2 : std::max(t.g2, 0.0);
    hessian->noalias() += (g2 / volume) * b * b.transpose();
  }
  return energy;
}

}  // namespace sinew
