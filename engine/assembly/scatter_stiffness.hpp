#pragma once
// Adds sum_e coeff[e] * R_e Ke R_e^T into the values of a matrix with the system pattern.
#include "engine/model.hpp"

namespace sinew {

// Adds coeff * K (an element matrix over its nodes, padded to 8) at the element's scatter
// positions. Not thread-safe across elements sharing nodes: callers go colour by colour
// (Model::element_colors) or through Model::element_schedule.
void scatter_element_matrix(const Model& model, int e, const Mat24& K, double coeff, double* values);
// The same for a tet's 12 x 12 matrix (element e has 4 nodes).
void scatter_element_matrix(const Model& model, int e, const Mat12& K, double coeff, double* values);

// Elements with coeff[e] == 0 are skipped. Parallel by colour, deterministic.
void scatter_warped_stiffness(const Model& model, const std::vector<Mat3>& R,
                              const std::vector<double>& coeff, double* values);

}  // namespace sinew
