#pragma once
// Strain-limit constraints of paper 001, section 3, for one tet4 element.
//
// F = Ds Dm^-1 = sum_a x_a dN_a^T (dN_a: row a of dN_dX, the rest-space gradient of shape
// function a), so dF(r, c) / dx_a(r) = dN_a(c) and dC/dx_a = (dC/dF) dN_a.
// F = U diag(s) V^T is the rotation-variant SVD (det U = det V = +1; only s_3 may be
// negative, so an inverted tet violates every compress limit of its smallest axis).
//
// Limits smin_j, smax_j hold along material axis j = column m_j of `frame` (rest
// coordinates; frame = I gives the paper's global axes e_j). Principal axis i of the
// deformation is v_i = V e_i, so the paper's cosine e_i^T V^T e_j (eqs. 7-8) becomes
//   c_ij = v_i . m_j = (V^T M)(i, j),   a_ij = |c_ij|.
// Beyond the paper: M may be any rotation, per body or per element (e.g. a fibre
// direction), so the limits follow the material. Rotating the rest shape and M together
// (F -> F Q^T, M -> Q M) leaves every C unchanged, as does any world rotation (F -> R F).
//
// Constraints (all C >= 0, dimensionless, in units of stretch: C = 0.01 is 1 % of strain
// away from the limit, whatever the mode; the activation margin and the solver tolerance
// are measured in these units):
//   Hyperbolic (default, eqs. 7-8, 11-12): the limit of axis j projected onto principal
//     axis i with p = 1/|cos| is smin_ji = 1 + (smin_j - 1) / a_ij; multiplied by a_ij
//       C_min_ji = a_ij (s_i - 1) - (smin_j - 1)
//       C_max_ji = (smax_j - 1) - a_ij (s_i - 1)
//     i.e. the strain of s_i projected onto m_j against that axis' strain limit. 18 per tet.
//     No constraint where a_ij <= 1e-12 (the projected limit is infinite).
//     Beyond the paper, near repeated singular values: the paper's a_ij = |c_ij| depends on
//     which principal axes the SVD picks in a plane of (nearly) equal stretches, where any
//     pair is as good: at s_i = s_l = 1.027 with m_j in their plane, |c_ij| may be anything
//     in [0, 1], so C_max_ji jumps between -0.007 and +0.02 under a perturbation of F as
//     small as one likes; SQP then never settles (the fingers of fig. 3 did not reach the
//     1e-3 tolerance in a third of their frames) and finds states where a 2 % limit holds
//     a 2.7 % fibre stretch. Here
//       a_ij^2 = c_ij^2 + sum_{l != i} w(|s_i - s_l| / kStrainLimitBlendGap) c_lj^2,
//     w(t) = 1 - 3 t^2 + 2 t^3 for t < 1, 0 after (C1): the paper's |c_ij| once the
//     stretches are 2 % apart; at equal stretches, the length of m_j's projection onto
//     their plane, the same for every choice of axes in it (for m_j in that plane,
//     a_ij (s_i - 1) is then the fibre strain along m_j, as the paper intends). a_ij >= |c_ij|: the
//     blend only tightens, it never hides a violation the paper's form would show.
//   Orthogonal (eqs. 19-20): smin_ji = 1 + (smin_j - 1) a_ij, and so on:
//       C_min_ji = (s_i - 1) - a_ij (smin_j - 1)
//       C_max_ji = a_ij (smax_j - 1) - (s_i - 1)
//     18 per tet; a principal axis orthogonal to every limited axis gets the limits [1, 1].
//   Linear (eqs. 21-22): L_i(l) = || diag(l_1, l_2, l_3) V e_i || in the paper's notation,
//     V e_i being principal axis i in the frame of the limits, with components c_ij:
//       L_i(l) = sqrt(sum_j (l_j c_ij)^2)
//       C_min_i = s_i - L_i(smin),  C_max_i = L_i(smax) - s_i.   6 per tet.
//     Note: the text calls this the intersection of the principal axis with the ellipsoid of
//     semi-axes l_j, which would be 1 / sqrt(sum_j (c_ij / l_j)^2); the equation (the image
//     of the unit direction under diag(l), also a point of that ellipsoid) is implemented.
//   Isotropic (eqs. 9-10): C_min_i = s_i - smin, C_max_i = smax - s_i, 6 per tet, with
//     smin = max_j smin_j and smax = min_j smax_j over the limited axes (the tightest;
//     equal to the plain isotropic limits when the three axes agree). The frame is unused.
//
// Free axes: smin_j <= 0 means "no compress limit" and smax_j = +inf (any non-finite
// value) "no stretch limit" along m_j; such a limit produces no constraint. In Linear mode a
// free compress limit contributes l_j = 0 to L_i(smin) and a free stretch limit makes
// L_i(smax) infinite (no constraint) unless principal axis i is orthogonal to m_j
// (|c_ij| <= 1e-12). Limits are meant to bracket 1 (smin_j <= 1 <= smax_j).
//
// Jacobians (eqs. 13, 16-18): every C is C(s_i, c_i1, c_i2, c_i3), so
//   dC/dF = p ds_i/dF + sum_j q_j dc_ij/dF,  ds_i/dF = u_i v_i^T (eq. 13),
//   dc_ij/dF(r, c) = (dV/dF(r, c) e_i) . m_j with dV from Papadopoulo-Lourakis
//   (engine/math/svd_derivative.hpp; eqs. 14-16), and per mode
//     Hyperbolic  min: p = a_ij, q_j = sign(c_ij) (s_i - 1)     (eq. 17)
//                 max: p = -a_ij, q_j = -sign(c_ij) (s_i - 1)   (eq. 18)
//                 where the blend is on (above), C also depends on s_l and c_lj (l != i):
//                 strain_limit.cpp, add_hyperbolic_terms, differentiates a_ij in full
//                 (exact, like every mode, where the gaps exceed the tolerance below).
//     Orthogonal  min: p = 1, q_j = -sign(c_ij) (smin_j - 1)
//                 max: p = -1, q_j = sign(c_ij) (smax_j - 1)
//     Linear      min: p = 1, q_j = -smin_j^2 c_ij / L_i(smin)
//                 max: p = -1, q_j = smax_j^2 c_ij / L_i(smax)
//     Isotropic   p = +-1, q = 0.
//   sign(0) = 0 (a subgradient of |c| at its kink); L_i <= 1e-12 gives q = 0.
// Near repeated singular values dV is regularised (svd_derivative.hpp), here with a wider
// gap, kStrainLimitGapTolerance: where two singular values are closer than that (relative
// to max(s_1, 1)) the principal frame of the pair is only partly coupled to F, which keeps
// the rows well scaled (the exact coupling grows like (s_i - 1) / gap). Values are exact;
// Jacobians are exact whenever all gaps exceed the tolerance.
#include <array>
#include <cstdint>
#include <limits>

#include "engine/core/types.hpp"
#include "engine/math/rotation_variant_svd.hpp"

namespace sinew {

enum class StrainLimitMode { Hyperbolic, Orthogonal, Linear, Isotropic };

constexpr double kStrainLimitGapTolerance = 1e-3;
constexpr double kStrainLimitBlendGap = 0.02;

struct StrainLimitSpec {
  Vec3 smin = Vec3::Zero();  // per material axis; <= 0: free
  Vec3 smax = Vec3::Constant(std::numeric_limits<double>::infinity());  // per axis; +inf: free
  Mat3 frame = Mat3::Identity();  // columns m_j: material axes in rest coords (orthonormal)
  StrainLimitMode mode = StrainLimitMode::Hyperbolic;
  bool pair_cuts = true;  // hyperbolic mode: the cuts near equal stretches (below)
  double pair_cut_gap = kStrainLimitBlendGap;  // cuts where s_p - s_{p+1} < this (<= the blend gap)
};

// Constraint index k = 6 i + 2 j + side (i principal axis, j material axis, side 0 compress /
// 1 stretch); Linear and Isotropic use j = 0. Stable keys: row_key(RowKind::Strain, tet, k).
constexpr int kStrainLimitCount = 18;
constexpr int strain_limit_index(int i, int j, int side) { return 6 * i + 2 * j + side; }

// Beyond the paper, hyperbolic mode ("pair cuts", spec.pair_cuts): extra rows where two
// principal stretches nearly meet, s_p - s_{p+1} < spec.pair_cut_gap (at most
// kStrainLimitBlendGap; pair p = 0: axes 0 and 1; p = 1: axes 1 and 2). There the larger of the pair is a cone in F, s_p = max of
// |F w| over unit w in the pair's plane, and each linearisation of its stretch row
// under-predicts it by about move^2 / gap (docs/ARCHITECTURE.md, "Why the pressed finger
// never settles"); the smaller, a min, is over-predicted, which its compress rows miss. The
// cuts hold the stretch along the two directions halfway between the pair's axes,
// w = (v_p +- v_{p+1}) / sqrt 2, fixed in the material for the row's linearisation:
//   stretch cut of axis p:      C = (smax_j - 1) - a_pj (|F w| - 1)
//   compress cut of axis p + 1: C = a_(p+1)j (|F w| - 1) - (smin_j - 1)
// with the blended cosine of that axis' own row and |F w| = sqrt((s_p^2 + s_{p+1}^2) / 2)
// at the SVD's F. Since s_{p+1} <= |F w| <= s_p, a cut is never below its axis' row: it
// reports no violation of its own (violations are measured on the 18 constraints alone).
// |F w| at fixed w is smooth (its linearisation misses by move^2 / |F w|, not / gap), and
// with the pair's own rows the cuts sample the plane every 45 degrees, so a QP step can no
// longer turn the stretch to a direction its rows do not see. Jacobian (w held):
//   dC/dF = -+((|F w| - 1) da/dF + a n w^T),  n = F w / |F w|  (- stretch, + compress),
// da/dF as in the rows' blended cosine. No curvature block (strain_limit_curvature.hpp:
// Gauss-Newton for the cuts).
// Index k = 18 + 12 p + 4 j + 2 side + sign (side 0 compress, 1 stretch; sign 0: w with +,
// 1: with -): 42 indices in all, bit masks of 64 bits.
constexpr int kStrainCutFirst = 18;
constexpr int kStrainRowIndexCount = 42;
constexpr int strain_cut_index(int p, int j, int side, int sign) { return kStrainCutFirst + 12 * p + 4 * j + 2 * side + sign; }
using StrainRowMask = uint64_t;  // bit k: row index k

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat43 = Eigen::Matrix<double, 4, 3>;

// Values of the constraints a tet has (bit k of `present`); C[k] is meaningful only there.
struct StrainLimitValues {
  std::array<double, kStrainRowIndexCount> C{};  // the 18 constraints, then the cuts
  StrainRowMask present = 0;
};

StrainLimitValues compute_strain_limit_values(const StrainLimitSpec& spec,
                                              const RotationVariantSvd& svd);

// Whether constraint k with value C becomes a row: C below the margin, or bit k of `keep`
// set (it carried force earlier in the step).
inline bool strain_row_wanted(int k, double C, double margin, StrainRowMask keep) {
  return C < margin || (keep >> k & 1);
}

// The tightest limits on each principal stretch s_i implied by the constraints
// (-inf / +inf where none): all C >= 0 exactly when smin(i) <= s_i <= smax(i).
struct ProjectedStrainLimits {
  Vec3 smin, smax;
};

ProjectedStrainLimits compute_projected_strain_limits(const StrainLimitSpec& spec,
                                                      const RotationVariantSvd& svd);

struct StrainLimitRow {
  int index = 0;     // k, see strain_limit_index
  double value = 0;  // C_k
  Mat3 dF;           // dC_k/dF
  Vec12 jac;         // dC_k/dx over the 4 nodes (node-major)
};

struct StrainLimitRows {
  int count = 0;
  std::array<StrainLimitRow, kStrainRowIndexCount> row;  // the first `count` are valid
};

// Rows of one tet: every constraint it has with C_k < margin, or whose bit k is set in
// `keep` (rows that carried force earlier in the step). margin = +inf returns them all.
// Allocates nothing.
void evaluate_strain_limit(const StrainLimitSpec& spec, const Mat3& F, const Mat43& dN_dX,
                           double margin, StrainRowMask keep, StrainLimitRows& out,
                           double gap_tolerance = kStrainLimitGapTolerance);
// The same from F's rotation-variant SVD, when the caller has it already.
void evaluate_strain_limit(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const Mat43& dN_dX,
                           double margin, StrainRowMask keep, StrainLimitRows& out,
                           double gap_tolerance = kStrainLimitGapTolerance);
// The same for a caller that knows the tet has rows (keep != 0, or its
// worst_strain_violation above -margin): no values-only pass first. The same rows.
void evaluate_strain_limit_rows(const StrainLimitSpec& spec, const RotationVariantSvd& svd, const Mat43& dN_dX,
                                double margin, StrainRowMask keep, StrainLimitRows& out,
                                double gap_tolerance = kStrainLimitGapTolerance);

// Cut k's material direction w at this SVD, and cut k with its direction held at w (the
// function its row linearises; at w = strain_cut_direction(svd, k) its value is C[k]).
Vec3 strain_cut_direction(const RotationVariantSvd& svd, int k);
double strain_cut_value(const StrainLimitSpec& spec, const RotationVariantSvd& svd, int k, const Vec3& w);

// Worst violation max_k(-C_k) of one tet (positive when violated; -inf when it has no
// constraint). No gradients.
double worst_strain_violation(const StrainLimitSpec& spec, const Mat3& F);
double worst_strain_violation(const StrainLimitSpec& spec, const RotationVariantSvd& svd);
// The same from the tet's values.
double worst_strain_violation(const StrainLimitValues& values);

}  // namespace sinew
