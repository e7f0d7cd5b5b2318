#pragma once
// Quantities of one state that the work-precision study records besides the surfaces.
#include "engine/world.hpp"

namespace sinew::wp {

// Kinetic + elastic + gravity potential energy, J. Elastic: 1/2 u^T Ke u of a linear
// corotational element (u its corotated displacement), the material energy of a
// hyperelastic one. Potential: -sum m g . x.
double total_energy(const World& world);

// The worst stretch |F m_j| of any element of a strain-limited body past a limit of its
// material axis m_j (smin_j - |F m_j| or |F m_j| - smax_j), 0 when within every limit.
// Independent of the projection mode (paper 001), unlike the solver's own violation.
double axis_strain_excess(const World& world);

struct VolumeChange {
  double worst = 0;  // max over elements of |J - 1|, J = det F at the element centre
  double total = 0;  // sum J V / sum V - 1
};
VolumeChange volume_change(const World& world);

}  // namespace sinew::wp
