#pragma once
// As-rigid-as-possible: the corotational energy of paper 003 eq. 3 without its volume term,
//   Psi = mu ||F - R||^2,   mu = mu_L,
// so P = 2 mu (F - R) and the eigensystem is scaling 2 mu I, flip 2 mu,
// twist 2 mu - 4 mu / (sigma_i + sigma_j) (denominator floored as in corotational.hpp).
// Its linearisation is 2 mu_L eps: Hooke's law only for nu = 0 (no resistance to volume change
// beyond shear). Departure: none beyond corotational's.
#include "engine/materials/corotational.hpp"

namespace sinew {

class Arap : public Corotational {
 public:
  explicit Arap(const MaterialParameters& params);
  const char* name() const override { return "arap"; }
};

}  // namespace sinew
