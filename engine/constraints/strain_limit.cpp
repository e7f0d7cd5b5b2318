#include "engine/constraints/strain_limit.hpp"

#include <algorithm>
#include <cmath>

#include "engine/math/svd_derivative.hpp"

namespace sinew {

namespace {

constexpr double kTiny = 1e-12;
constexpr double kInf = std::numeric_limits<double>::infinity();

bool has_min(double smin) { return std::isfinite(smin) && smin > 0; }
bool has_max(double smax) { return std::isfinite(smax); }
double sign_of(double c) { return c > 0 ? 1.0 : (c < 0 ? -1.0 : 0.0); }

// One constraint C(s_i, c_i.) with dC = p ds_i + sum_j q_j dc_ij (header: the table per mode).
struct Term {
  int k;
  int i;
  double C;
  double p;
  Vec3 q;
};

struct Terms {
  int count = 0;
  std::array<Term, kStrainLimitCount> term;
  void add(int k, int i, double C, double p, const Vec3& q) { term[count++] = {k, i, C, p, q}; }
};

// Every constraint the tet has, with its value and derivative coefficients, in index order.
void collect_terms(const StrainLimitSpec& spec, const RotationVariantSvd& svd, Terms& out) {
  out.count = 0;
  const Mat3 c = svd.V.transpose() * spec.frame;  // c(i, j) = v_i . m_j
  const Vec3& s = svd.S;
  const Vec3& lo = spec.smin;
  const Vec3& hi = spec.smax;
  switch (spec.mode) {
    case StrainLimitMode::Hyperbolic:
      // C_min = a (s_i - 1) - (smin_j - 1), C_max = (smax_j - 1) - a (s_i - 1)  (eqs. 11-12)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double a = std::abs(c(i, j));
          if (a <= kTiny) continue;
          const Vec3 q = sign_of(c(i, j)) * (s(i) - 1) * Vec3::Unit(j);
          if (has_min(lo(j)))
            out.add(strain_limit_index(i, j, 0), i, a * (s(i) - 1) - (lo(j) - 1), a, q);
          if (has_max(hi(j)))
            out.add(strain_limit_index(i, j, 1), i, (hi(j) - 1) - a * (s(i) - 1), -a, -q);
        }
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
  Terms terms;
  collect_terms(spec, svd, terms);
  StrainLimitValues out;
  for (int t = 0; t < terms.count; ++t) {
    out.C[terms.term[t].k] = terms.term[t].C;
    out.present |= 1u << terms.term[t].k;
  }
  return out;
}

ProjectedStrainLimits compute_projected_strain_limits(const StrainLimitSpec& spec,
                                                      const RotationVariantSvd& svd) {
  // At fixed V every constraint is affine in s_i with slope p != 0 (+-1, or +-a_ij > 1e-12):
  // it vanishes at s_i - C / p, a lower bound when p > 0 and an upper one when p < 0.
  Terms terms;
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
                           double margin, uint32_t keep, StrainLimitRows& out,
                           double gap_tolerance) {
  out.count = 0;
  const RotationVariantSvd svd = compute_rotation_variant_svd(F);
  Terms terms;
  collect_terms(spec, svd, terms);
  bool any = false;
  for (int t = 0; t < terms.count; ++t)
    any = any || terms.term[t].C < margin || (keep >> terms.term[t].k & 1u);
  if (!any) return;

  // dc_ij/dF(r, c) = (dV/dF(r, c) e_i) . m_j, so sum_j q_j dc_ij/dF(r, c) = dV e_i . (M q).
  const SvdDerivative d = compute_svd_derivative(svd, gap_tolerance);
  for (int t = 0; t < terms.count; ++t) {
    const Term& term = terms.term[t];
    if (!(term.C < margin || (keep >> term.k & 1u))) continue;
    const int i = term.i;
    const Vec3 w = spec.frame * term.q;
    // dC/dF = p u_i v_i^T + (dV e_i) . w, entry by entry
    Mat3 G = term.p * svd.U.col(i) * svd.V.col(i).transpose();
    if (term.q.squaredNorm() > 0)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) G(r, c) += d.dV[r][c].col(i).dot(w);
    StrainLimitRow& row = out.row[out.count++];
    row.index = term.k;
    row.value = term.C;
    for (int a = 0; a < 4; ++a) row.jac.segment<3>(3 * a) = G * dN_dX.row(a).transpose();
  }
}

double worst_strain_violation(const StrainLimitSpec& spec, const Mat3& F) {
  Terms terms;
  collect_terms(spec, compute_rotation_variant_svd(F), terms);
  double worst = -kInf;
  for (int t = 0; t < terms.count; ++t) worst = std::max(worst, -terms.term[t].C);
  return worst;
}

}  // namespace sinew
