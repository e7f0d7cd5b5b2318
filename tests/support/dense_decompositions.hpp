#pragma once
// Dense symmetric eigen- and singular-value decompositions for the tests' checks, compiled
// once (dense_decompositions.cpp): each fixed-size Eigen solver a test file instantiates
// costs it 10-20 s of compile time, and CI compiles the tests twice. Dynamic-size Eigen runs
// the same algorithms (Householder tridiagonalisation + implicit QR; two-sided Jacobi), so the
// results agree with the fixed-size solvers to round-off.
#include "engine/core/types.hpp"

namespace sinew::test {

struct SymmetricEigen {
  VecX values;   // ascending
  MatX vectors;  // orthonormal columns, vectors.col(i) belongs to values(i)
};

// A must be symmetric (only its lower triangle is read).
SymmetricEigen symmetric_eigen(const MatX& A);
VecX symmetric_eigenvalues(const MatX& A);
double min_eigenvalue(const MatX& A);
double max_eigenvalue(const MatX& A);

VecX singular_values(const MatX& A);  // descending

}  // namespace sinew::test
