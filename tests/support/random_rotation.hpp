#pragma once
// A random rotation for tests: a normalised Gaussian quaternion (uniform over rotations),
// drawing four normals from `rng`.
#include <Eigen/Geometry>
#include <random>

#include "engine/core/types.hpp"

namespace sinew::test {

inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

}  // namespace sinew::test
