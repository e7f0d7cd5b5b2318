#include <algorithm>

#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "engine/step/stages.hpp"

namespace sinew {
namespace {

// Builds every kind's rows at positions x; returns the worst violation by kind
// (energy: Ue/Umax - 1). A new kind of constraint adds a line here, not a solver branch.
double build_rows(const Model& model, const VecX& x, const std::vector<uint64_t>& keep, RowTable& rows) {
  rows.clear();
  return add_energy_limit_rows(model, x, model.solver.activation_margin, keep, rows);
}

double warm_lambda(const std::vector<std::pair<uint64_t, double>>& warm, uint64_t key) {
  const auto it = std::lower_bound(warm.begin(), warm.end(), std::make_pair(key, -1e300));
  return (it != warm.end() && it->first == key) ? it->second : 0.0;
}

// W = J A^-1 J^T from the stencils of J and the columns Y = A^-1 J^T.
MatX delassus(const Model& model, const RowTable& rows, const MatX& Y) {
  const int m = rows.size();
  MatX W = MatX::Zero(m, m);
  for (int i = 0; i < m; ++i)
    for (int k = rows.begin[i]; k < rows.begin[i + 1]; ++k) {
      const int f = model.free_index[rows.nodes[k]];
      if (f >= 0) W.row(i) += rows.jac[k].transpose() * Y.middleRows<3>(3 * f);
    }
  return 0.5 * (W + W.transpose());
}

}  // namespace

void solve_constraints(const Model& model, LinearSolver& solver, State& s) {
  StepProfile& profile = s.profile;
  const int stage = static_cast<int>(Stage::Constraints);
  const bool limited = std::any_of(model.element_Umax.begin(), model.element_Umax.end(),
                                   [](double u) { return u > 0; });
  if (!limited) {
    profile.skipped[stage] = "scene has no constraints";
    return;
  }
  const SolverDesc& cfg = model.solver;
  const double h = model.h;
  const VecX x0 = s.x;
  VecX v_star_free(3 * model.num_free);
  for (int n = 0; n < model.num_nodes; ++n)
    if (model.free_index[n] >= 0) v_star_free.segment<3>(3 * model.free_index[n]) = s.v.segment<3>(3 * n);
  VecX v = s.v;

  std::vector<uint64_t> keep;
  for (const auto& [key, lambda] : s.warm_start)
    if (lambda > 0) keep.push_back(key);
  int sqp = 0, pgs = 0;
  double worst = 0;
  for (int k = 0;; ++k) {
    worst = build_rows(model, x0 + h * v, keep, s.rows);
    const int m = s.rows.size();
    if (m == 0 || worst <= cfg.sqp_tolerance || k == cfg.sqp_max_iterations) break;
    ++sqp;

    // Y = A^-1 J^T over free DOFs (rows of J for fixed nodes drop out: their v is 0).
    MatX& Y = s.constraint_dirs;
    MatX Jt = MatX::Zero(3 * model.num_free, m);
    VecX c(m);
    for (int i = 0; i < m; ++i) {
      double jv = 0;
      for (int e = s.rows.begin[i]; e < s.rows.begin[i + 1]; ++e) {
        const int node = s.rows.nodes[e], f = model.free_index[node];
        if (f < 0) continue;
        Jt.block<3, 1>(3 * f, i) = s.rows.jac[e];
        jv += s.rows.jac[e].dot(v_star_free.segment<3>(3 * f) - v.segment<3>(3 * node));
      }
      // Linearised at the current iterate: C_k + h J (v - v_k) >= 0, v = v* + Y lambda.
      c[i] = s.rows.value[i] / h + jv;
      s.rows.lambda[i] = warm_lambda(s.warm_start, s.rows.key[i]);
    }
    solver.solve_many(Jt, Y);
    const MatX W = delassus(model, s.rows, Y);
    pgs += solve_pgs(W, c, s.rows, cfg.pgs_max_iterations, cfg.pgs_tolerance).iterations;

    const VecX v_free = v_star_free + Y * Eigen::Map<const VecX>(s.rows.lambda.data(), m);
    for (int n = 0; n < model.num_nodes; ++n) {
      const int f = model.free_index[n];
      if (f >= 0) v.segment<3>(3 * n) = v_free.segment<3>(3 * f);
    }
    s.warm_start.clear();
    keep.clear();
    for (int i = 0; i < m; ++i) {
      s.warm_start.emplace_back(s.rows.key[i], s.rows.lambda[i]);
      if (s.rows.lambda[i] > 0) keep.push_back(s.rows.key[i]);
    }
    std::sort(s.warm_start.begin(), s.warm_start.end());
    std::sort(keep.begin(), keep.end());
  }
  s.v = v;
  if (sqp == 0) {
    profile.skipped[stage] = s.rows.size() ? "no row violated" : "no near-active constraint";
    s.warm_start.clear();
  }
  profile.rows["energy"] = s.rows.count(RowKind::Energy);
  profile.iterations["sqp"] += sqp;
  profile.iterations["pgs"] += pgs;
  profile.violation["energy"] = std::max(0.0, worst);
}

}  // namespace sinew
