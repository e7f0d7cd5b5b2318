#pragma once
// An isotropic material: Psi depends on F only through its signed singular values, so its
// Hessian has the closed-form eigensystem of eigen_projection.hpp and its projected Hessian is
// that eigensystem with the eigenvalues clamped at 0 (paper 003, sec. 4.6).
#include "engine/materials/eigen_projection.hpp"
#include "engine/materials/material.hpp"

namespace sinew {

class IsotropicMaterial : public Material {
 public:
  // The closed-form eigensystem of hessian(F): the same matrix, assembled from the SVD frame.
  virtual SvdEigensystem eigensystem(const Mat3& F) const = 0;
  Mat9 projected_hessian(const Mat3& F) const override {
    return assemble_eigensystem(eigensystem(F), true);
  }
};

}  // namespace sinew
