// assemble_system (b, and A where the step needs the matrix), assemble_system_matrix and
// scatter_warped_stiffness write A and b through the scatter map of the system pattern, and
// multiply_step_system applies A without it; here they are checked against the plain
// element-by-element sums of eq. 19 assembled densely, and for bitwise equality on 1 and 2
// threads.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <random>

#include "engine/assembly/element_kernels.hpp"
#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/model.hpp"
#include "engine/step/stages.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

// A hex body with a fixed face, a tet body (split lattice) with mass damping and a
// Stable Neo-Hookean hex body, which assemble_system leaves to solve_newton.
SceneDesc three_bodies() {
  return parse_scene_text(R"({"bodies": [
    {"name": "hex", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1]}], "cell_size": 0.1,
     "material": {"E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"mass": 0.5, "stiffness": 0.02},
     "fixed": [{"half_space": {"point": [-0.15, 0, 0], "normal": [1, 0, 0]}}]},
    {"name": "tet", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1], "center": [0, 1, 0]}],
     "elements": "tet", "cell_size": 0.1, "material": {"E": 2e5, "nu": 0.4, "rho": 500},
     "damping": {"mass": 0.1, "stiffness": 0.01}},
    {"name": "snh", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1], "center": [0, -1, 0]}],
     "cell_size": 0.1, "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 800}}]})",
                          "three", ".");
}

// Moves every node by up to 2 cm and gives it a velocity and an external force, so that
// rotations, forces and warped blocks are all non-trivial.
void perturb(State& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < s.x.size(); ++i) {
    s.x[i] += 0.02 * u(rng);
    s.v[i] = 0.5 * u(rng);
    s.external_force[i] = u(rng);
  }
}

MatX dense(const SparseMatrix& A) { return MatX(A); }

}  // namespace

TEST_CASE("assemble_system: A and b equal the element-by-element sums of eq. 19") {
  World world(build_model(three_bodies(), [](const std::string&) {}));
  const Model& m = world.model();
  State& s = world.mutable_state();
  perturb(s, 7);
  assemble_system(m, s);
  const double h = m.h;

  // Reference: dense A = sum_e k_e R Ke R^T + (1 + h alpha) M over free DOFs, and
  // b = M v + h (M g + f_external + f_elastic), each element's matrix taken whole
  // (element_warped_stiffness).
  const int n = 3 * m.num_free;
  MatX A = MatX::Zero(n, n);
  VecX force = VecX::Zero(3 * m.num_nodes);
  int linear_elements = 0;
  for (int e = 0; e < m.num_elements; ++e) {
    const Body& body = m.bodies[m.element_body[e]];
    const ElementNodes nodes = gather_element_nodes(m, s.x, e);
    const CorotatedElement c = compute_corotated_element(m, e, nodes);
    if (body.hyperelastic) continue;  // its R: the test case below
    CHECK((s.R[e] - c.R).norm() == 0);
    ++linear_elements;
    const Vec24 f = element_elastic_force(m, e, c.R, c.u);
    Mat24 K;
    element_warped_stiffness(m, e, c.R, K);
    const double k = h * body.damping_stiffness + h * h;
    for (int a = 0; a < nodes.count; ++a) {
      force.segment<3>(3 * m.element_nodes[e][a]) += f.segment<3>(3 * a);
      for (int b = 0; b < nodes.count; ++b) {
        const int fa = m.free_index[m.element_nodes[e][a]], fb = m.free_index[m.element_nodes[e][b]];
        if (fa >= 0 && fb >= 0) A.block<3, 3>(3 * fa, 3 * fb) += k * K.block<3, 3>(3 * a, 3 * b);
      }
    }
  }
  REQUIRE(linear_elements > 0);
  REQUIRE(linear_elements < m.num_elements);  // the SNH body is there and left out
  VecX b(n);
  for (int node = 0; node < m.num_nodes; ++node) {
    const int fi = m.free_index[node];
    if (fi < 0) continue;
    const double mass = m.node_mass[node];
    const double alpha = m.bodies[m.node_body[node]].damping_mass;
    A.block<3, 3>(3 * fi, 3 * fi).diagonal().array() += (1 + h * alpha) * mass;
    b.segment<3>(3 * fi) = mass * s.v.segment<3>(3 * node) +
                           h * (mass * m.gravity + s.external_force.segment<3>(3 * node) + force.segment<3>(3 * node));
  }

  // Both sum the same terms, in other orders: round-off of a few ulps of the largest term.
  const MatX assembled = dense(s.system);
  CHECK((assembled - A).cwiseAbs().maxCoeff() <= 1e-13 * A.cwiseAbs().maxCoeff());
  CHECK((s.rhs - b).cwiseAbs().maxCoeff() <= 1e-13 * b.cwiseAbs().maxCoeff());
  // Blocks (a, b) and (b, a) are R Ke_ab R^T and its transpose up to the order of the sums.
  CHECK((assembled - assembled.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * A.cwiseAbs().maxCoeff());
}

TEST_CASE("scatter_warped_stiffness adds sum_e coeff_e R Ke R^T") {
  World world(build_model(three_bodies(), [](const std::string&) {}));
  const Model& m = world.model();
  State& s = world.mutable_state();
  perturb(s, 11);
  assemble_system(m, s);  // rotations
  std::vector<double> coeff(m.num_elements);
  for (int e = 0; e < m.num_elements; ++e) coeff[e] = e % 3 == 0 ? 0.0 : 0.25 + 0.01 * e;
  SparseMatrix M = s.system;
  const MatX before = dense(M);
  scatter_warped_stiffness(m, s.R, coeff, M.valuePtr());

  MatX expected = before;
  for (int e = 0; e < m.num_elements; ++e) {
    if (coeff[e] == 0) continue;
    Mat24 K;
    element_warped_stiffness(m, e, s.R[e], K);
    for (int a = 0; a < element_node_count(m, e); ++a)
      for (int b = 0; b < element_node_count(m, e); ++b) {
        const int fa = m.free_index[m.element_nodes[e][a]], fb = m.free_index[m.element_nodes[e][b]];
        if (fa >= 0 && fb >= 0) expected.block<3, 3>(3 * fa, 3 * fb) += coeff[e] * K.block<3, 3>(3 * a, 3 * b);
      }
  }
  CHECK((dense(M) - expected).cwiseAbs().maxCoeff() <= 1e-13 * expected.cwiseAbs().maxCoeff());
}

TEST_CASE("assemble_system: a hyperelastic element's rotation is computed only under an energy limit") {
  // Stage 1 leaves hyperelastic elements to solve_newton; only an energy limit's curvature
  // (R Ke R^T) needs their R. Without a limit it keeps its value from before (the identity).
  const char* scene = R"({"bodies": [
    {"name": "limited", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}], "cell_size": 0.1,
     "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 800}, "energy_limit": {"Umax": 1}},
    {"name": "free", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1], "center": [0, 1, 0]}],
     "cell_size": 0.1, "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.45, "rho": 800}}]})";
  World world(build_model(parse_scene_text(scene, "two", "."), [](const std::string&) {}));
  const Model& m = world.model();
  State& s = world.mutable_state();
  perturb(s, 5);
  assemble_system(m, s);
  int limited = 0, free = 0;
  for (int e = 0; e < m.num_elements; ++e) {
    const Mat3 R = compute_corotated_element(m, e, gather_element_nodes(m, s.x, e)).R;
    REQUIRE((R - Mat3::Identity()).norm() > 1e-3);  // the perturbation rotated every element
    if (m.element_Umax[e] > 0) {
      ++limited;
      CHECK((s.R[e] - R).norm() == 0);
    } else {
      ++free;
      CHECK(s.R[e] == Mat3::Identity());
    }
  }
  CHECK(limited == m.bodies[0].num_elements());
  CHECK(free == m.bodies[1].num_elements());
}

// Bodies of 432 hexes and 768 tets, so that 2 threads do take part in the element loops;
// corotational only, so that assemble_system leaves the matrix out (CHOLMOD).
const char* const kTwoLargeBodies = R"({"bodies": [
    {"name": "hex", "shape": [{"type": "box", "half_extents": [0.3, 0.15, 0.15]}], "cell_size": 0.05,
     "material": {"E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"mass": 0.5, "stiffness": 0.02},
     "fixed": [{"half_space": {"point": [-0.29, 0, 0], "normal": [1, 0, 0]}}]},
    {"name": "tet", "shape": [{"type": "box", "half_extents": [0.2, 0.1, 0.1], "center": [0, 1, 0]}],
     "elements": "tet", "cell_size": 0.05, "material": {"E": 2e5, "nu": 0.4, "rho": 500}}]})";

TEST_CASE("assemble_system: A and b are bitwise the same on 1 and 2 threads") {
  const auto assemble = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    World world(build_model(parse_scene_text(kTwoLargeBodies, "big", "."), [](const std::string&) {}));
    size_t widest = 0;
    for (const auto& colour : world.model().element_colors) widest = std::max(widest, colour.size());
    REQUIRE(widest >= 54);
    State& s = world.mutable_state();
    perturb(s, 3);
    assemble_system(world.model(), s);
    assemble_system_matrix(world.model(), s);
    return std::make_pair(VecX(Eigen::Map<const VecX>(s.system.valuePtr(), s.system.nonZeros())), s.rhs);
  };
  const auto [A1, b1] = assemble(1);
  const auto [A2, b2] = assemble(2);
  CHECK(A1 == A2);
  CHECK(b1 == b2);
}

TEST_CASE("multiply_step_system: without the matrix, A x element by element equals the assembled A x, and so does b - A v0") {
  // assemble_system leaves the matrix out, and the product goes element by element; the
  // same A assembled gives the same product up to the order of its sums.
  const auto products = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    World world(build_model(parse_scene_text(kTwoLargeBodies, "big", "."), [](const std::string&) {}));
    const Model& m = world.model();
    State& s = world.mutable_state();
    perturb(s, 9);
    assemble_system(m, s);
    REQUIRE_FALSE(s.system_assembled);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    VecX x(3 * m.num_free);
    for (int i = 0; i < x.size(); ++i) x[i] = u(rng);
    VecX free_product, assembled_product;
    multiply_step_system(m, s, x, free_product);
    // Two columns in one pass: each the product above, up to the order of Ke's sums.
    VecX y = x.reverse(), pair_x, pair_y, single_y;
    multiply_step_system(m, s, x, pair_x, y, pair_y);
    multiply_step_system(m, s, y, single_y);
    // The start-of-step residual b - A v0 from assemble_system's element pass.
    VecX v0(3 * m.num_free);
    for (int n = 0; n < m.num_nodes; ++n)
      if (const int f = m.free_index[n]; f >= 0) v0.segment<3>(3 * f) = s.v.segment<3>(3 * n);
    const VecX start_residual = s.start_residual;
    assemble_system_matrix(m, s);
    REQUIRE(s.system_assembled);
    multiply_step_system(m, s, x, assembled_product);
    VecX assembled_v0;
    multiply_step_system(m, s, v0, assembled_v0);
    // Both sum the same terms in other orders: each output is at most 81 entries of A (27
    // nodes of a hex lattice) times x, each entry a sum of up to 8 rotated element blocks
    // (products of three 3x3 factors) plus the mass, so a few hundred roundings of at most
    // 81 |A|_max |x|_max: 1e-13 of that is 450 ulps.
    const double scale = MatX(s.system).cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff() * 81;
    CHECK((free_product - assembled_product).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    CHECK((pair_x - free_product).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    CHECK((pair_y - single_y).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    // b - A v0 against the assembled A; its terms are at most |b|_max and 81 |A|_max |v0|_max.
    const double residual_scale = s.rhs.cwiseAbs().maxCoeff() + MatX(s.system).cwiseAbs().maxCoeff() * v0.cwiseAbs().maxCoeff() * 81;
    CHECK((start_residual - (s.rhs - assembled_v0)).cwiseAbs().maxCoeff() <= 1e-13 * residual_scale);
    return std::make_pair(free_product, VecX(pair_y));
  };
  const auto [one_thread, one_thread_pair] = products(1);
  const auto [two_threads, two_threads_pair] = products(2);
  CHECK(one_thread == two_threads);
  CHECK(one_thread_pair == two_threads_pair);
}
