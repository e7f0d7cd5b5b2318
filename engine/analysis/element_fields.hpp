#pragma once
// Per-element quantities for export and colour maps.
#include <map>
#include <string>
#include <vector>

#include "engine/model.hpp"
#include "engine/state.hpp"

namespace sinew {

// Corotated displacement of element e at the current positions, with the element's
// current rotation recomputed from x.
Vec24 element_corotated_displacement(const Model& model, const VecX& x, int e, Mat3* rotation = nullptr);

// "energy_density": stored elastic energy 1/2 u^T Ke u per rest volume, J/m^3;
// "volume_ratio": det F at the cell centre; "energy_ratio": Ue / Umax (0 without a limit).
std::map<std::string, std::vector<double>> compute_element_fields(const Model& model, const State& state);

}  // namespace sinew
