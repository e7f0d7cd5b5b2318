#pragma once
// Hyperelastic materials (paper 003 and the family it compares against). Every material is a
// small type with the same methods; elements (hex8 at 8 Gauss points, tet4 at one point) call
// them with the deformation gradient F and never see the material's formulas.
//
// Conventions: Psi is energy per unit rest volume (J/m^3). Matrices are flattened column-major,
// vec(F) = (F00, F10, F20, F01, ...), so Hessian(i, j) = d^2 Psi / d vec(F)_i d vec(F)_j.
#include <memory>
#include <string>

#include "engine/core/types.hpp"

namespace sinew {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

struct MaterialParameters {
  double young = 0;    // E, Pa
  double poisson = 0;  // nu
  // Extensions of paper 003, sec. 7 (used only by their materials):
  double fung_c = 1;           // Fung exponent scale (dimensionless)
  double arruda_boyce_n = 8;   // Arruda-Boyce chain segments N (locking stretch sqrt(N))
};

// Lame parameters of linear elasticity from (E, nu): mu_L = E / (2 (1 + nu)),
// lambda_L = E nu / ((1 + nu)(1 - 2 nu)). Every material maps these to its own constants so that
// its linearisation at F = I is Hooke's law (except ARAP, which has no volume term).
struct LameParameters {
  double mu = 0;
  double lambda = 0;
};
// Throws std::invalid_argument unless E > 0 and -1 < nu < 1/2.
LameParameters lame_parameters(const MaterialParameters& params);

class InvariantMaterial;

class Material {
 public:
  virtual ~Material() = default;
  virtual const char* name() const = 0;
  // False where the energy is undefined (classic Neo-Hookean with J <= 0). There energy()
  // returns +infinity and pk1()/hessian() stay finite but are no longer its derivatives (see the
  // material's header). Every other material is defined for every finite F.
  virtual bool is_defined(const Mat3& /*F*/) const { return true; }
  virtual double energy(const Mat3& F) const = 0;          // Psi(F)
  virtual Mat3 pk1(const Mat3& F) const = 0;               // P = dPsi/dF
  virtual Mat9 hessian(const Mat3& F) const = 0;           // d^2 Psi / dF^2
  virtual Mat9 projected_hessian(const Mat3& F) const = 0; // nearest PSD (eigenvalues clamped at 0)
  // This material as an invariant one (invariant_material.hpp), or null: the element assembly
  // then takes its terms once per point and a tet's Hessian term by term.
  virtual const InvariantMaterial* as_invariant() const { return nullptr; }
};

// Names: "stable_neo_hookean", "neo_hookean", "corotational", "arap", "stvk", "fung",
// "arruda_boyce". Throws std::invalid_argument for an unknown name (message lists the names).
std::unique_ptr<Material> make_material(const std::string& name, const MaterialParameters& params);

// The names make_material accepts, for error messages and --help.
const std::vector<std::string>& material_names();

}  // namespace sinew
