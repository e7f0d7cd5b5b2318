#include <algorithm>

#include "engine/assembly/scatter_stiffness.hpp"
#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/lcp_pgs.hpp"
#include "engine/step/stages.hpp"

namespace sinew {
namespace {

// Builds every kind's rows at the iterate (positions x = x0 + h v, velocities v);
// returns the worst violation relative to each kind's tolerance (<= 1 means converged).
// A new kind of constraint adds a line here, not a branch in the solver.
double build_rows(const Model& model, const VecX& x, const VecX& v, const std::vector<uint64_t>& keep,
                  RowTable& rows, StepProfile& profile) {
  (void)v;
  rows.clear();
  const double energy = add_energy_limit_rows(model, x, model.solver.activation_margin, keep, rows);
  profile.violation["energy"] = std::max(0.0, energy);
  return energy / model.solver.sqp_tolerance;
}

bool has_constraints(const Model& model) {
  return std::any_of(model.element_Umax.begin(), model.element_Umax.end(), [](double u) { return u > 0; });
}

double warm_lambda(const std::vector<std::pair<uint64_t, double>>& warm, uint64_t key) {
  const auto it = std::lower_bound(warm.begin(), warm.end(), std::make_pair(key, -1e300));
  return (it != warm.end() && it->first == key) ? it->second : 0.0;
}

VecX gather_free(const Model& model, const VecX& full) {
  VecX out(3 * model.num_free);
  for (int n = 0; n < model.num_nodes; ++n)
    if (model.free_index[n] >= 0) out.segment<3>(3 * model.free_index[n]) = full.segment<3>(3 * n);
  return out;
}

void scatter_free(const Model& model, const VecX& free, VecX& full) {
  for (int n = 0; n < model.num_nodes; ++n) {
    const int f = model.free_index[n];
    full.segment<3>(3 * n) = f >= 0 ? Vec3(free.segment<3>(3 * f)) : Vec3::Zero();
  }
}

// W = J Y from the stencils of J and the columns Y = H^-1 J^T.
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

// The SQP Hessian H = A + h sum_i lambda_i curvature_i R_e Ke R_e^T (the constraint term
// of the Lagrangian; lambda is a force impulse, so one h). Returns false when it is A.
bool build_sqp_system(const Model& model, State& s) {
  std::vector<double>& coeff = s.element_scratch;
  coeff.assign(model.num_elements, 0.0);
  bool any = false;
  for (int i = 0; i < s.rows.size(); ++i)
    if (s.rows.element[i] >= 0 && s.rows.lambda[i] > 0) {
      coeff[s.rows.element[i]] += model.h * s.rows.lambda[i] * s.rows.curvature[i];
      any = true;
    }
  if (!any) return false;
  s.sqp_system = s.system;
  scatter_warped_stiffness(model, s.R, coeff, s.sqp_system.valuePtr());
  return true;
}

}  // namespace

// SQP on   min_v 1/2 v^T A v - b^T v   s.t.  C(x0 + h v) >= 0   (paper 000, section 5):
// each iteration linearises the rows at x_k = x0 + h v_k, solves the QP
//   H dv = -(A v_k - b) + J^T lambda,   C_k + h J dv >= 0,   0 <= lambda
// through the LCP  W lambda + c >= 0 (eq. 23) with W = J H^-1 J^T by PGS, and sets
// v_k+1 = v_k + dv. On the first iteration H = A (the step's factorisation) and the QP is
// exactly the paper's LCP; later ones add the constraints' curvature to H, without which
// the iteration cycles once the limits carry large forces.
void solve_constraints(const Model& model, LinearSolver& solver, State& s) {
  StepProfile& profile = s.profile;
  const int stage = static_cast<int>(Stage::Constraints);
  if (!has_constraints(model)) {
    profile.skipped[stage] = "scene has no constraints";
    return;
  }
  const SolverDesc& cfg = model.solver;
  const double h = model.h;
  const VecX x0 = s.x;
  VecX v_free = gather_free(model, s.v);  // v_k; starts at v*
  bool factor_is_A = true;

  std::vector<uint64_t> keep;
  for (const auto& [key, lambda] : s.warm_start)
    if (lambda > 0) keep.push_back(key);
  int sqp = 0, pgs = 0;
  for (int k = 0;; ++k) {
    const double worst = build_rows(model, x0 + h * s.v, s.v, keep, s.rows, profile);
    const int m = s.rows.size();
    if (m == 0 || worst <= 1 || k == cfg.sqp_max_iterations) break;
    ++sqp;
    for (int i = 0; i < m; ++i) s.rows.lambda[i] = warm_lambda(s.warm_start, s.rows.key[i]);

    // Factorise H (or keep A's factorisation) and take the Newton step without constraints.
    VecX v_base = v_free;
    const bool curved = build_sqp_system(model, s);
    if (curved || !factor_is_A) {
      if (!solver.factorize(curved ? s.sqp_system : s.system)) break;
      factor_is_A = !curved;
    }
    if (k > 0) {
      VecX step;
      solver.solve(s.system * v_free - s.rhs, step);
      v_base -= step;
    }

    MatX Jt = MatX::Zero(3 * model.num_free, m);
    for (int i = 0; i < m; ++i)
      for (int e = s.rows.begin[i]; e < s.rows.begin[i + 1]; ++e) {
        const int f = model.free_index[s.rows.nodes[e]];
        if (f >= 0) Jt.block<3, 1>(3 * f, i) = s.rows.jac[e];
      }
    MatX& Y = s.constraint_dirs;
    solver.solve_many(Jt, Y);
    const MatX W = delassus(model, s.rows, Y);
    // C_k + h J (v - v_k) >= 0 with v = v_base + Y lambda.
    const VecX c = Eigen::Map<const VecX>(s.rows.value.data(), m) / h + Jt.transpose() * (v_base - v_free);
    pgs += solve_pgs(W, c, s.rows, cfg.pgs_max_iterations, cfg.pgs_tolerance).iterations;
    v_free = v_base + Y * Eigen::Map<const VecX>(s.rows.lambda.data(), m);
    scatter_free(model, v_free, s.v);

    // Rows stay for the rest of the step once active, so the active set only grows.
    s.warm_start.clear();
    for (int i = 0; i < m; ++i) {
      s.warm_start.emplace_back(s.rows.key[i], s.rows.lambda[i]);
      keep.push_back(s.rows.key[i]);
    }
    std::sort(s.warm_start.begin(), s.warm_start.end());
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  }
  if (sqp == 0) {
    profile.skipped[stage] = s.rows.size() ? "no row violated" : "no near-active constraint";
    s.warm_start.clear();
  }
  for (int kind = 0; kind < kRowKindCount; ++kind)
    if (const int n = s.rows.count(static_cast<RowKind>(kind))) profile.rows[row_kind_name(static_cast<RowKind>(kind))] = n;
  profile.iterations["sqp"] += sqp;
  profile.iterations["pgs"] += pgs;
}

}  // namespace sinew
