#pragma once
// Isotropic Hookean elasticity (paper 000, eq. 1): sigma = C eps in Voigt form with
// engineering shear strains (xx, yy, zz, xy, yz, zx). E1, E2, E3 as in paper 000, sec. 4.2.
#include <Eigen/Core>

namespace sinew {

struct IsotropicElasticity {
  double E1 = 0;  // Y (1 - nu) / ((1 + nu)(1 - 2 nu))   (lambda + 2 mu)
  double E2 = 0;  // Y nu / ((1 + nu)(1 - 2 nu))         (lambda)
  double E3 = 0;  // Y / (2 (1 + nu))                    (mu)

  static IsotropicElasticity from_young_poisson(double young, double poisson) {
    const double d = (1 + poisson) * (1 - 2 * poisson);
    return {young * (1 - poisson) / d, young * poisson / d, young / (2 * (1 + poisson))};
  }

  Eigen::Matrix<double, 6, 6> voigt_matrix() const {
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C(i, j) = (i == j) ? E1 : E2;
    for (int i = 3; i < 6; ++i) C(i, i) = E3;
    return C;
  }
};

}  // namespace sinew
