#include "engine/constraints/strain_limit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/math/svd_derivative.hpp"

namespace sinew {

namespace {

constexpr double kTiny = 1e-12;
constexpr double kInf = std::numeric_limits<double>::infinity();

bool has_min(double smin) { return std::isfinite(smin) && smin > 0; }
bool has_max(double smax) { return std::isfinite(smax); }
double sign_of(double c) { return c > 0 ? 1.0 : (c < 0 ? -1.0 : 0.0); }

// One constraint C(s, c) with dC = sum_l P_l ds_l + sum_lj Q_lj dc_lj (header: the table per
// mode). p: the slope dC/ds_i at fixed cosines, which bounds s_i (compute_projected_strain_limits).
struct Term {
  int k;
  int i;
  double C;
  double p;
  Vec3 P;
  Mat3 Q;
};

struct Terms {
  // false: values and slopes only (C, p), for screening and values; P and Q are left unset.
  // Either way C comes from the same operations, so both agree bit for bit.
  bool derivatives = true;
  // With derivatives, P and Q only for the terms that become rows (C below `margin`, or
  // index k in `keep`); the others' are left unset (the flat finger's candidate tets: ~450
  // rows of ~3,600 terms).
  double margin = std::numeric_limits<double>::infinity();
  StrainRowMask keep = ~StrainRowMask{0};
  int count = 0;
  std::array<Term, kStrainLimitCount> term;
  bool wanted(int k, double C) const { return derivatives && strain_row_wanted(k, C, margin, keep); }
  // A constraint of s_i and row i of c only: P = p e_i, Q row i = q.
  void add(int k, int i, double C, double p, const Vec3& q) {
    Term& t = term[count++];
    t.k = k, t.i = i, t.C = C, t.p = p;
    if (!wanted(k, C)) return;
    t.P = p * Vec3::Unit(i);
    t.Q.setZero();
    t.Q.row(i) = q.transpose();
  }
  // Value and slope only (P and Q not wanted).
  void add(int k, int i, double C, double p) {
    Term& t = term[count++];
    t.k = k, t.i = i, t.C = C, t.p = p;
  }
  void add(int k, int i, double C, double p, const Vec3& P, const Mat3& Q) {
    Term& t = term[count++];
    t.k = k, t.i = i, t.C = C, t.p = p;
    if (wanted(k, C)) t.P = P, t.Q = Q;
  }
};

// Weight of principal axis l in axis i's cosine when s_i and s_l are t * kStrainLimitBlendGap
// apart: 1 at t = 0, 0 from t = 1 on, C1 (smoothstep); and dw/dt.
double blend_weight(double t) { return t >= 1 ? 0.0 : 1 - t * t * (3 - 2 * t); }
double blend_weight_slope(double t) { return t >= 1 ? 0.0 : -6 * t * (1 - t); }

// c(i, j) = v_i . m_j.
Mat3 axis_cosines(const StrainLimitSpec& spec, const RotationVariantSvd& svd) { return svd.V.transpose() * spec.frame; }

// Principal axis i's blend weights w(l) = w_il (w(i) = 0) and the blended cosine
// a_ij = sqrt(c_ij^2 + sum_l w_il c_lj^2) (header).
Vec3 blend_weights(const Vec3& s, int i) {
  Vec3 w = Vec3::Zero();
  for (int l = 0; l < 3; ++l)
    if (l != i) w(l) = blend_weight(std::abs(s(i) - s(l)) / kStrainLimitBlendGap);
  return w;
}
double blended_cosine(const Mat3& c, const Vec3& w, int i, int j) {
  double a2 = c(i, j) * c(i, j);
  for (int l = 0; l < 3; ++l) a2 += w(l) * c(l, j) * c(l, j);
  return std::sqrt(a2);
}

// Whether pair p (axes p, p + 1) is close enough for its cuts (header), and the stretch
// |F w| along either cut's direction.
bool has_pair_cuts(const StrainLimitSpec& spec, const Vec3& s, int p) {
  return spec.pair_cuts && s(p) - s(p + 1) < std::min(spec.pair_cut_gap, kStrainLimitBlendGap);
}
double cut_stretch(const Vec3& s, int p) { return std::sqrt(0.5 * (s(p) * s(p) + s(p + 1) * s(p + 1))); }

// The hyperbolic constraints of principal stretch s against axis j's limits (eqs. 11-12).
double hyperbolic_compress(double a, double s, double smin) { return a * (s - 1) - (smin - 1); }
double hyperbolic_stretch(double a, double s, double smax) { return (smax - 1) - a * (s - 1); }

// Every cut the tet has (header), in index order: visit(k, p, i, j, a, t, C) with pair p,
// the cut's principal axis i (p for a stretch cut, p + 1 for a compress cut), its material
// axis j, blended cosine a_ij, stretch t = |F w| and value C.
template <class Visit>
void for_each_pair_cut(const StrainLimitSpec& spec, const Vec3& s, const Mat3& c, Visit visit) {
  for (int p = 0; p < 2; ++p) {
    if (!has_pair_cuts(spec, s, p)) continue;
    const double t = cut_stretch(s, p);
    if (!(t > kTiny)) continue;  // both stretches ~0: no direction to hold
    const Vec3 w_compress = blend_weights(s, p + 1), w_stretch = blend_weights(s, p);
    for (int j = 0; j < 3; ++j)
      for (int side = 0; side < 2; ++side) {
        const int i = side == 1 ? p : p + 1;
        if (side == 1 ? !has_max(spec.smax(j)) : !has_min(spec.smin(j))) continue;
        const double a = blended_cosine(c, side == 1 ? w_stretch : w_compress, i, j);
        if (a <= kTiny) continue;
        const double C = side == 1 ? hyperbolic_stretch(a, t, spec.smax(j)) : hyperbolic_compress(a, t, spec.smin(j));
        for (int sign = 0; sign < 2; ++sign) visit(strain_cut_index(p, j, side, sign), p, i, j, a, t, C);
      }
  }
}

// Hyperbolic constraints with the blended cosine (header): a_ij^2 = c_ij^2 + sum_l w_il c_lj^2.
void add_hyperbolic_terms(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const Mat3& c, Terms& out) {
  const Vec3& s = svd.S;
  for (int i = 0; i < 3; ++i) {
    const Vec3 w = blend_weights(s, i);
    Vec3 dw_ds = Vec3::Zero();  // dw_il / ds_i (= -dw_il / ds_l)
    if (out.derivatives)
      for (int l = 0; l < 3; ++l)
        if (l != i)
          dw_ds(l) = blend_weight_slope(std::abs(s(i) - s(l)) / kStrainLimitBlendGap) * sign_of(s(i) - s(l)) /
                     kStrainLimitBlendGap;
    for (int j = 0; j < 3; ++j) {
      const double a = blended_cosine(c, w, i, j);
      if (a <= kTiny) continue;
      const int k_min = strain_limit_index(i, j, 0), k_max = strain_limit_index(i, j, 1);
      const bool min = has_min(spec.smin(j)), max = has_max(spec.smax(j));
      const double C_min = hyperbolic_compress(a, s(i), spec.smin(j)), C_max = hyperbolic_stretch(a, s(i), spec.smax(j));
      if (!(min && out.wanted(k_min, C_min)) && !(max && out.wanted(k_max, C_max))) {
        if (min) out.add(k_min, i, C_min, a);
        if (max) out.add(k_max, i, C_max, -a);
        continue;
      }
      // dC_min = a ds_i + (s_i - 1) da, da = (c_ij dc_ij + sum_l (w_il c_lj dc_lj
      //          + c_lj^2 / 2 dw_il)) / a;  C_max = const - (the same): every term negated.
      Vec3 P = a * Vec3::Unit(i);
      Mat3 Q = Mat3::Zero();
      const double g = (s(i) - 1) / a;
      Q(i, j) = g * c(i, j);
      for (int l = 0; l < 3; ++l) {
        if (l == i) continue;
        Q(l, j) = g * w(l) * c(l, j);
        const double dP = 0.5 * g * c(l, j) * c(l, j) * dw_ds(l);
        P(i) += dP;
        P(l) -= dP;
      }
      if (min) out.add(k_min, i, C_min, a, P, Q);
      if (max) out.add(k_max, i, C_max, -a, -P, -Q);
    }
  }
}

// The hyperbolic constraints' values alone (every build evaluates every limited tet): the
// operations of add_hyperbolic_terms, without its Terms.
StrainLimitValues hyperbolic_values(const StrainLimitSpec& spec, const RotationVariantSvd& svd) {
  StrainLimitValues out;
  const Mat3 c = axis_cosines(spec, svd);
  const Vec3& s = svd.S;
  for (int i = 0; i < 3; ++i) {
    const Vec3 w = blend_weights(s, i);
    for (int j = 0; j < 3; ++j) {
      const double a = blended_cosine(c, w, i, j);
      if (a <= kTiny) continue;
      if (has_min(spec.smin(j))) {
        const int k = strain_limit_index(i, j, 0);
        out.C[k] = hyperbolic_compress(a, s(i), spec.smin(j));
        out.present |= StrainRowMask{1} << k;
      }
      if (has_max(spec.smax(j))) {
        const int k = strain_limit_index(i, j, 1);
        out.C[k] = hyperbolic_stretch(a, s(i), spec.smax(j));
        out.present |= StrainRowMask{1} << k;
      }
    }
  }
  for_each_pair_cut(spec, s, c, [&](int k, int, int, int, double, double, double C) {
    out.C[k] = C;
    out.present |= StrainRowMask{1} << k;
  });
  return out;
}

// da_ij of the blended cosine as the coefficients of ds (P_a) and of dc_lj (column j of Q,
// Q_a): the terms add_hyperbolic_terms scales by (s_i - 1).
void blended_cosine_slopes(const Mat3& c, const Vec3& s, int i, int j, double a, Vec3& P_a, Vec3& Q_a) {
  const Vec3 w = blend_weights(s, i);
  P_a.setZero();
  Q_a.setZero();
  Q_a(i) = c(i, j) / a;
  for (int l = 0; l < 3; ++l) {
    if (l == i) continue;
    Q_a(l) = w(l) * c(l, j) / a;
    const double dw_ds =
        blend_weight_slope(std::abs(s(i) - s(l)) / kStrainLimitBlendGap) * sign_of(s(i) - s(l)) / kStrainLimitBlendGap;
    const double dP = 0.5 * c(l, j) * c(l, j) * dw_ds / a;
    P_a(i) += dP;
    P_a(l) -= dP;
  }
}

// dC/dF of dC = sum_l P_l ds_l + sum_lj Q_lj dc_lj: sum_l P_l u_l v_l^T + sum_l (dV e_l) .
// (M Q^T e_l), entry by entry (dc_lj = (dV e_l) . m_j): <dV, W> with W = M Q^T, = <Omega_V, X>
// with X = V^T W, Omega_V antisymmetric: sum over pairs k < l of Omega_V(k, l) (X_kl - X_lk).
Mat3 gradient_in_F(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const SvdRotationDerivative& d,
                   const Vec3& P, const Mat3& Q) {
  Mat3 G = svd.U * P.asDiagonal() * svd.V.transpose();
  if (Q.squaredNorm() > 0) {
    const Mat3 X = svd.V.transpose() * (spec.frame * Q.transpose());
    const Vec3 x(X(0, 1) - X(1, 0), X(0, 2) - X(2, 0), X(1, 2) - X(2, 1));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) G(r, c) += d.omega_V[r][c].dot(x);
  }
  return G;
}

// Every constraint the tet has, with its value and derivative coefficients, in index order.
void collect_terms(const StrainLimitSpec& spec, const RotationVariantSvd& svd, Terms& out) {
  out.count = 0;
  const Mat3 c = axis_cosines(spec, svd);
  const Vec3& s = svd.S;
  const Vec3& lo = spec.smin;
  const Vec3& hi = spec.smax;
  switch (spec.mode) {
    case StrainLimitMode::Hyperbolic:
      // C_min = a (s_i - 1) - (smin_j - 1), C_max = (smax_j - 1) - a (s_i - 1)  (eqs. 11-12)
      add_hyperbolic_terms(spec, svd, c, out);
      break;
    case StrainLimitMode::Orthogonal:
      // C_min = (s_i - 1) - a (smin_j - 1), C_max = a (smax_j - 1) - (s_i - 1)  (eqs. 19-20)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double a = std::abs(c(i, j));
          const double sg = sign_of(c(i, j));
          if (has_min(lo(j)))
            out.add(strain_limit_index(i, j, 0), i, (s(i) - 1) - a * (lo(j) - 1), 1.0,
                    -sg * (lo(j) - 1) * Vec3::Unit(j));
          if (has_max(hi(j)))
            out.add(strain_limit_index(i, j, 1), i, a * (hi(j) - 1) - (s(i) - 1), -1.0,
                    sg * (hi(j) - 1) * Vec3::Unit(j));
        }
      break;
    case StrainLimitMode::Linear: {
      // L_i(l) = sqrt(sum_j (l_j c_ij)^2); C_min = s_i - L_i(smin), C_max = L_i(smax) - s_i
      // (eqs. 21-22); free compress limits count as l_j = 0.
      const Vec3 l_lo(has_min(lo(0)) ? lo(0) : 0.0, has_min(lo(1)) ? lo(1) : 0.0,
                      has_min(lo(2)) ? lo(2) : 0.0);
      const bool any_lo = (l_lo.array() > 0).any();
      for (int i = 0; i < 3; ++i) {
        if (any_lo) {
          const Vec3 w = l_lo.cwiseProduct(l_lo).cwiseProduct(c.row(i).transpose());
          const double L = l_lo.cwiseProduct(c.row(i).transpose()).norm();
          out.add(strain_limit_index(i, 0, 0), i, s(i) - L, 1.0,
                  L > kTiny ? Vec3(-w / L) : Vec3::Zero());
        }
        bool bounded = true;
        Vec3 l_hi = Vec3::Zero();
        for (int j = 0; j < 3; ++j) {
          if (has_max(hi(j)))
            l_hi(j) = hi(j);
          else if (std::abs(c(i, j)) > kTiny)
            bounded = false;
        }
        if (bounded && (l_hi.array() > 0).any()) {
          const Vec3 w = l_hi.cwiseProduct(l_hi).cwiseProduct(c.row(i).transpose());
          const double L = l_hi.cwiseProduct(c.row(i).transpose()).norm();
          out.add(strain_limit_index(i, 0, 1), i, L - s(i), -1.0,
                  L > kTiny ? Vec3(w / L) : Vec3::Zero());
        }
      }
      break;
    }
    case StrainLimitMode::Isotropic: {
      // C_min = s_i - smin, C_max = smax - s_i with the tightest limits  (eqs. 9-10)
      double tight_lo = -kInf, tight_hi = kInf;
      for (int j = 0; j < 3; ++j) {
        if (has_min(lo(j))) tight_lo = std::max(tight_lo, lo(j));
        if (has_max(hi(j))) tight_hi = std::min(tight_hi, hi(j));
      }
      for (int i = 0; i < 3; ++i) {
        if (tight_lo > -kInf)
          out.add(strain_limit_index(i, 0, 0), i, s(i) - tight_lo, 1.0, Vec3::Zero());
        if (tight_hi < kInf)
          out.add(strain_limit_index(i, 0, 1), i, tight_hi - s(i), -1.0, Vec3::Zero());
      }
      break;
    }
  }
}

}  // namespace

StrainLimitValues compute_strain_limit_values(const StrainLimitSpec& spec,
                                              const RotationVariantSvd& svd) {
  if (spec.mode == StrainLimitMode::Hyperbolic) return hyperbolic_values(spec, svd);
  Terms terms;
  terms.derivatives = false;
  collect_terms(spec, svd, terms);
  StrainLimitValues out;
  for (int t = 0; t < terms.count; ++t) {
    out.C[terms.term[t].k] = terms.term[t].C;
    out.present |= StrainRowMask{1} << terms.term[t].k;
  }
  return out;
}

ProjectedStrainLimits compute_projected_strain_limits(const StrainLimitSpec& spec,
                                                      const RotationVariantSvd& svd) {
  // At fixed V every constraint is affine in s_i with slope p != 0 (+-1, or +-a_ij > 1e-12):
  // it vanishes at s_i - C / p, a lower bound when p > 0 and an upper one when p < 0.
  Terms terms;
  terms.derivatives = false;
  collect_terms(spec, svd, terms);
  ProjectedStrainLimits out{Vec3::Constant(-kInf), Vec3::Constant(kInf)};
  for (int t = 0; t < terms.count; ++t) {
    const Term& term = terms.term[t];
    const double bound = svd.S(term.i) - term.C / term.p;
    if (term.p > 0)
      out.smin(term.i) = std::max(out.smin(term.i), bound);
    else
      out.smax(term.i) = std::min(out.smax(term.i), bound);
  }
  return out;
}

void evaluate_strain_limit(const StrainLimitSpec& spec, const Mat3& F, const Mat43& dN_dX,
                           double margin, StrainRowMask keep, StrainLimitRows& out,
                           double gap_tolerance) {
  evaluate_strain_limit(spec, compute_rotation_variant_svd(F), dN_dX, margin, keep, out, gap_tolerance);
}

void evaluate_strain_limit(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const Mat43& dN_dX,
                           double margin, StrainRowMask keep, StrainLimitRows& out, double gap_tolerance) {
  out.count = 0;
  // Values first: most tets of a scene have no row near its limit (the flat finger: 231 of
  // 324), and their derivative coefficients would go unused. Not when rows are kept (rows
  // that carried force, or the curvature's probes, 10 calls per tet): they are wanted.
  if (keep == 0) {
    const StrainLimitValues values = compute_strain_limit_values(spec, svd);
    bool any = false;
    for (int k = 0; k < kStrainLimitCount; ++k) any = any || ((values.present >> k & 1) && values.C[k] < margin);
    if (!any) return;
  }
  evaluate_strain_limit_rows(spec, svd, dN_dX, margin, keep, out, gap_tolerance);
}

void evaluate_strain_limit_rows(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const Mat43& dN_dX,
                                double margin, StrainRowMask keep, StrainLimitRows& out, double gap_tolerance) {
  out.count = 0;
  Terms terms;
  terms.derivatives = true;
  terms.margin = margin;
  terms.keep = keep;
  collect_terms(spec, svd, terms);

  // dc_ij/dF(r, c) = (dV/dF(r, c) e_i) . m_j, so sum_j q_j dc_ij/dF(r, c) = dV e_i . (M q).
  const SvdRotationDerivative d = compute_svd_rotation_derivative(svd, gap_tolerance);
  const auto add_row = [&](int k, double C, const Mat3& G) {
    StrainLimitRow& row = out.row[out.count++];
    row.index = k;
    row.value = C;
    row.dF = G;
    for (int a = 0; a < 4; ++a) row.jac.segment<3>(3 * a) = G * dN_dX.row(a).transpose();
  };
  for (int t = 0; t < terms.count; ++t) {
    const Term& term = terms.term[t];
    if (!terms.wanted(term.k, term.C)) continue;  // C below the margin, or kept: P and Q are set
    add_row(term.k, term.C, gradient_in_F(spec, svd, d, term.P, term.Q));
  }
  if (spec.mode != StrainLimitMode::Hyperbolic) return;
  const Mat3 c = axis_cosines(spec, svd);
  const Vec3& s = svd.S;
  for_each_pair_cut(spec, s, c, [&](int k, int p, int i, int j, double a, double t, double C) {
    if (!strain_row_wanted(k, C, margin, keep)) return;
    // Stretch: dC/dF = -((t - 1) da/dF + a n w^T); compress: the same with + . w = (v_p +-
    // v_{p+1}) / sqrt 2 held in the material, n = F w / t.
    Vec3 P_a, Q_a_col;
    blended_cosine_slopes(c, s, i, j, a, P_a, Q_a_col);
    Mat3 Q_a = Mat3::Zero();
    Q_a.col(j) = Q_a_col;
    const double pm = (k - kStrainCutFirst) % 2 == 0 ? 1.0 : -1.0;
    const Vec3 dir = strain_cut_direction(svd, k);
    const Vec3 n = (s(p) * svd.U.col(p) + pm * s(p + 1) * svd.U.col(p + 1)) / (std::sqrt(2.0) * t);
    const Mat3 G = gradient_in_F(spec, svd, d, (t - 1) * P_a, (t - 1) * Q_a) + a * n * dir.transpose();
    add_row(k, C, i == p ? Mat3(-G) : G);
  });
}

Vec3 strain_cut_direction(const RotationVariantSvd& svd, int k) {
  const int q = k - kStrainCutFirst, p = q / 12;
  const double pm = q % 2 == 0 ? 1.0 : -1.0;
  return (svd.V.col(p) + pm * svd.V.col(p + 1)) / std::sqrt(2.0);
}

double strain_cut_value(const StrainLimitSpec& spec, const RotationVariantSvd& svd, int k, const Vec3& w) {
  const int q = k - kStrainCutFirst, p = q / 12, j = q % 12 / 4, side = q % 4 / 2;
  const int i = side == 1 ? p : p + 1;
  const double a = blended_cosine(axis_cosines(spec, svd), blend_weights(svd.S, i), i, j);
  const double t = (svd.U * svd.S.asDiagonal() * svd.V.transpose() * w).norm();
  return side == 1 ? hyperbolic_stretch(a, t, spec.smax(j)) : hyperbolic_compress(a, t, spec.smin(j));
}

double worst_strain_violation(const StrainLimitSpec& spec, const Mat3& F) {
  return worst_strain_violation(spec, compute_rotation_variant_svd(F));
}

double worst_strain_violation(const StrainLimitSpec& spec, const RotationVariantSvd& svd) {
  return worst_strain_violation(compute_strain_limit_values(spec, svd));
}

double worst_strain_violation(const StrainLimitValues& values) {
  double worst = -kInf;
  for (int k = 0; k < kStrainLimitCount; ++k)
    if (values.present >> k & 1) worst = std::max(worst, -values.C[k]);
  return worst;
}

}  // namespace sinew
