#include "engine/constraints/strain_limit_rows.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cstring>

#include "engine/assembly/element_kernels.hpp"
#include "engine/constraints/strain_limit_curvature.hpp"

namespace sinew {

StrainLimitSpec strain_limit_spec(const StrainLimitDesc& desc) {
  StrainLimitSpec spec;
  spec.smin = desc.smin;
  spec.smax = desc.smax;
  spec.frame = desc.frame;
  spec.pair_cuts = desc.pair_cuts == "on";
  spec.mode = desc.mode == "orthogonal" ? StrainLimitMode::Orthogonal
              : desc.mode == "linear"   ? StrainLimitMode::Linear
              : desc.mode == "isotropic" ? StrainLimitMode::Isotropic
                                         : StrainLimitMode::Hyperbolic;
  return spec;
}

// add_strain_limit_rows' kept storage (kept_storage.hpp).
struct StrainRowBuffers {
  std::vector<double> worst;
  std::vector<double> cut_gaps;  // per element, its spec's pair_cut_gap (empty: the default)
  std::vector<StrainLimitSpec> body_specs;  // per body, its limits (tet_spec adds the tet's frame and gap)
  std::vector<RotationVariantSvd> svds;
  std::vector<StrainLimitValues> values;
  std::vector<std::pair<int, StrainRowMask>> kept;
  std::vector<int> candidates;
  std::vector<StrainRowMask> masks;  // per candidate, its kept constraints
  std::vector<StrainLimitRows> found;
  // A build with deferred Jacobians: its first row in the table, its margin (-1: none pending).
  int deferred_first_row = -1;
  double deferred_margin = 0;
};

namespace {

bool is_limited(const Model& model, int e) {
  return model.element_type[e] == ElementType::Tet4 && model.bodies[model.element_body[e]].strain_limit.enabled;
}

// Per body, its limits, once a build (strain_limit_spec reads the description's strings).
void update_body_specs(const Model& model, StrainRowBuffers& buffers) {
  buffers.body_specs.resize(model.bodies.size());
  for (size_t b = 0; b < model.bodies.size(); ++b) buffers.body_specs[b] = strain_limit_spec(model.bodies[b].strain_limit);
}

// The limits of tet e: its body's, in the tet's material frame (pair cuts within the
// default gap).
StrainLimitSpec tet_spec(const Model& model, int e) {
  StrainLimitSpec spec = strain_limit_spec(model.bodies[model.element_body[e]].strain_limit);
  spec.frame = model.element_strain_frame[e];
  return spec;
}

// The same from a build's buffers, with the tet's pair cuts' gap.
StrainLimitSpec tet_spec(const Model& model, int e, const StrainRowBuffers& buffers) {
  StrainLimitSpec spec = buffers.body_specs[model.element_body[e]];
  spec.frame = model.element_strain_frame[e];
  if (!buffers.cut_gaps.empty()) spec.pair_cut_gap = buffers.cut_gaps[e];
  return spec;
}

// The gap under which tet e's pairs get their cuts (strain_pair_cut_gaps).
double pair_cut_gap(const Model& model, const VecX& v_start, int e) {
  const Mat43 dN_dX = model.tet_gradients[model.element_reference[e]].topRows<4>();
  Mat3 dF = Mat3::Zero();
  for (int a = 0; a < 4; ++a) {
    const int f = model.free_index[model.element_nodes[e][a]];
    if (f >= 0) dF += v_start.segment<3>(3 * f) * dN_dX.row(a);
  }
  const double delta = model.h * dF.norm();
  return 4 * delta * delta / model.solver.strain_tolerance;
}

Mat3 tet_deformation_gradient(const Model& model, const VecX& x, int e) {
  return element_center_deformation_gradient(model, e, gather_element_nodes(model, x, e));
}

// Per element, the worst violation (-inf without strain limits) into `worst` and, for the
// rows, the SVD of its F and its constraint values (one SVD and one evaluation per tet and
// build) into `buffers`.
const std::vector<double>& worst_per_element(const Model& model, const VecX& x, std::vector<double>& worst,
                                             StrainRowBuffers* buffers = nullptr) {
  if (buffers) update_body_specs(model, *buffers);
  worst.assign(model.num_elements, -1e300);
  if (buffers) {
    buffers->svds.resize(model.num_elements);
    buffers->values.resize(model.num_elements);
  }
  // The SVDs four at a time (compute_rotation_variant_svds: the same bits as one at a time).
  tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 32), [&](const tbb::blocked_range<int>& range) {
    int tets[4];
    Mat3 F[4];
    RotationVariantSvd svds[4];
    int count = 0;
    const auto evaluate = [&] {
      if (count == 0) return;
      compute_rotation_variant_svds(F, svds, count);
      for (int k = 0; k < count; ++k) {
        const int e = tets[k];
        const StrainLimitValues values =
            compute_strain_limit_values(buffers ? tet_spec(model, e, *buffers) : tet_spec(model, e), svds[k]);
        worst[e] = worst_strain_violation(values);
        if (buffers) buffers->svds[e] = svds[k], buffers->values[e] = values;
      }
      count = 0;
    };
    for (int e = range.begin(); e < range.end(); ++e) {
      if (!is_limited(model, e)) continue;
      tets[count] = e;
      F[count++] = tet_deformation_gradient(model, x, e);
      if (count == 4) evaluate();
    }
    evaluate();
  });
  return worst;
}

// The rows of one tet without their Jacobians: those evaluate_strain_limit_rows makes (C
// below the margin, or kept), in its order (index order), from the values it would compute.
void rows_without_jacobians(const StrainLimitValues& values, double margin, StrainRowMask keep, StrainLimitRows& out) {
  out.count = 0;
  for (int k = 0; k < kStrainRowIndexCount; ++k)
    if ((values.present >> k & 1) && strain_row_wanted(k, values.C[k], margin, keep)) {
      StrainLimitRow& row = out.row[out.count++];
      row.index = k;
      row.value = values.C[k];
    }
}

double overall(const Model& model, const std::vector<double>& worst) {
  double w = -1;
  for (int e = 0; e < model.num_elements; ++e)
    if (is_limited(model, e)) w = std::max(w, worst[e]);
  return w;
}

}  // namespace

double add_strain_limit_rows(const Model& model, const VecX& x, double margin,
                             const std::vector<uint64_t>& keep, RowTable& rows,
                             KeptStorage<StrainRowBuffers>* storage, StrainJacobians jacobians,
                             const std::vector<double>* cut_gaps) {
  if (!model.has_strain_limits) return -1;
  // Deferred: the completion must find this build's buffers, whichever thread it runs on.
  assert(jacobians == StrainJacobians::Now || storage);
  StrainRowBuffers& buffers = kept_or_thread_local(storage);
  buffers.deferred_first_row = -1;
  assert(!cut_gaps || cut_gaps->empty() || cut_gaps->size() == static_cast<size_t>(model.num_elements));
  if (cut_gaps)
    buffers.cut_gaps = *cut_gaps;  // the deferred completion needs them (no allocation once sized)
  else
    buffers.cut_gaps.clear();
  const std::vector<RotationVariantSvd>& svds = buffers.svds;
  const std::vector<double>& worst = worst_per_element(model, x, buffers.worst, &buffers);
  // Kept constraints per tet, as bit masks over the constraint index k.
  std::vector<std::pair<int, StrainRowMask>>& kept = buffers.kept;
  std::vector<int>& candidates = buffers.candidates;
  std::vector<StrainLimitRows>& found = buffers.found;
  kept.clear();
  candidates.clear();
  for (uint64_t key : keep)
    if (row_key_kind(key) == RowKind::Strain) {
      const int e = static_cast<int>(row_key_first(key));
      const StrainRowMask bit = StrainRowMask{1} << row_key_second(key);
      if (kept.empty() || kept.back().first != e) kept.push_back({e, 0});
      kept.back().second |= bit;
    }
  std::sort(kept.begin(), kept.end());
  // Candidates and their kept masks in one walk over the elements and `kept` (both in
  // element order), no search per element.
  std::vector<StrainRowMask>& masks = buffers.masks;
  masks.clear();
  masks.reserve(model.num_elements);  // at the first build: a candidate per element at most
  auto next_kept = kept.begin();
  for (int e = 0; e < model.num_elements; ++e) {
    while (next_kept != kept.end() && next_kept->first < e) ++next_kept;
    const StrainRowMask mask = next_kept != kept.end() && next_kept->first == e ? next_kept->second : 0u;
    if (is_limited(model, e) && (worst[e] > -margin || mask != 0)) {
      candidates.push_back(e);
      masks.push_back(mask);
    }
  }
  // Grown, never shrunk: a StrainLimitRows is 8 kB, and resizing up value-initialises
  // (zeroes) every element added, at each build whose candidates outnumber the last one's.
  if (found.size() < candidates.size()) found.resize(candidates.size());
  const bool defer = jacobians == StrainJacobians::Deferred;
  tbb::parallel_for(size_t(0), candidates.size(), [&](size_t i) {
    const int e = candidates[i];
    if (defer) {
      rows_without_jacobians(buffers.values[e], margin, masks[i], found[i]);
      return;
    }
    const StrainLimitSpec spec = tet_spec(model, e, buffers);
    const Mat43 dN_dX = model.tet_gradients[model.element_reference[e]].topRows<4>();
    evaluate_strain_limit_rows(spec, svds[e], dN_dX, margin, masks[i], found[i]);  // a candidate has rows
  });
  if (defer) buffers.deferred_first_row = rows.size(), buffers.deferred_margin = margin;
  // Rows in element order: the table does not depend on the thread count. Deferred
  // Jacobians are zero until complete_strain_limit_jacobians.
  for (size_t i = 0; i < candidates.size(); ++i) {
    const int e = candidates[i];
    for (int r = 0; r < found[i].count; ++r) {
      const StrainLimitRow& row = found[i].row[r];
      const int r_index = rows.add_row(RowKind::Strain, row.value, 0.0, 1e300, row_key(RowKind::Strain, e, row.index));
      rows.element[r_index] = e;
      for (int a = 0; a < 4; ++a)
        rows.add_entry(model.element_nodes[e][a], defer ? Vec3::Zero() : Vec3(row.jac.segment<3>(3 * a)));
    }
  }
  return overall(model, worst);
}

void strain_pair_cut_gaps(const Model& model, const VecX& v_start, std::vector<double>& out) {
  out.clear();
  if (!model.has_strain_limits || v_start.size() != 3 * model.num_free) return;
  out.resize(model.num_elements);
  tbb::parallel_for(tbb::blocked_range<int>(0, model.num_elements, 64), [&](const tbb::blocked_range<int>& range) {
    for (int e = range.begin(); e < range.end(); ++e) out[e] = is_limited(model, e) ? pair_cut_gap(model, v_start, e) : 0.0;
  });
}

void complete_strain_limit_jacobians(const Model& model, RowTable& rows, KeptStorage<StrainRowBuffers>* storage) {
  StrainRowBuffers& buffers = kept_or_thread_local(storage);
  if (buffers.deferred_first_row < 0) return;
  const std::vector<int>& candidates = buffers.candidates;
  std::vector<StrainLimitRows>& found = buffers.found;
  // The SVDs of the build (nothing else has used the buffers since): the same rows, now
  // with their Jacobians.
  tbb::parallel_for(size_t(0), candidates.size(), [&](size_t i) {
    const int e = candidates[i];
    const Mat43 dN_dX = model.tet_gradients[model.element_reference[e]].topRows<4>();
    evaluate_strain_limit_rows(tet_spec(model, e, buffers), buffers.svds[e], dN_dX, buffers.deferred_margin, buffers.masks[i],
                               found[i]);
  });
  int r_index = buffers.deferred_first_row;
  for (size_t i = 0; i < candidates.size(); ++i)
    for (int r = 0; r < found[i].count; ++r, ++r_index) {
      const StrainLimitRow& row = found[i].row[r];
      assert(r_index < rows.size() && rows.kind[r_index] == RowKind::Strain &&
             rows.key[r_index] == row_key(RowKind::Strain, candidates[i], row.index) &&
             std::memcmp(&rows.value[r_index], &row.value, sizeof row.value) == 0);  // NaN too
      for (int a = 0; a < 4; ++a) rows.jac[rows.begin[r_index] + a] = row.jac.segment<3>(3 * a);
    }
  buffers.deferred_first_row = -1;
}

void add_strain_limit_curvatures(const Model& model, const VecX& x, RowTable& rows) {
  // Per tet, the rows to do as a StrainLimitRows holding only their indices (all that
  // compute_strain_limit_curvatures reads) and the first of its blocks in
  // rows.curvature_blocks (each row's index set here).
  struct Tet {
    int element;
    int first_block;
    StrainLimitRows wanted;
  };
  thread_local std::vector<Tet> tets_storage;  // kept storage
  std::vector<Tet>& tets = tets_storage;
  // Sized by the table's strain rows (at most a tet and a block each), as the solver's other
  // buffers: they grow only with it, not at every new count of rows with force.
  const int strain_rows = rows.count(RowKind::Strain);
  tets.reserve(strain_rows);
  rows.curvature_blocks.reserve(rows.curvature_blocks.size() + strain_rows);
  tets.clear();
  int blocks = static_cast<int>(rows.curvature_blocks.size());
  for (int i = 0; i < rows.size(); ++i) {
    if (rows.kind[i] != RowKind::Strain || rows.lambda[i] <= 0 || rows.curvature_block[i] >= 0) continue;
    // A cut: no curvature block (strain_limit_curvature.hpp; its Hessian, a (I - n n^T) / t
    // on w, is of the order of a well-separated row's, left to Gauss-Newton).
    if (row_key_second(rows.key[i]) >= kStrainCutFirst) continue;
    const int e = rows.element[i];
    if (tets.empty() || tets.back().element != e) tets.push_back({e, blocks, {}});
    Tet& tet = tets.back();
    rows.curvature_block[i] = blocks++;
    tet.wanted.row[tet.wanted.count++].index = static_cast<int>(rows.key[i] & 0xFFFFFF);
  }
  rows.curvature_blocks.resize(blocks);
  tbb::parallel_for(size_t(0), tets.size(), [&](size_t t) {
    const int e = tets[t].element;
    const StrainLimitSpec spec = tet_spec(model, e);
    const Mat43 dN_dX = model.tet_gradients[model.element_reference[e]].topRows<4>();
    std::array<Mat12, kStrainRowIndexCount> out;  // 47 KB on the task's stack
    compute_strain_limit_curvatures(spec, tet_deformation_gradient(model, x, e), dN_dX, tets[t].wanted, out);
    for (int r = 0; r < tets[t].wanted.count; ++r) rows.curvature_blocks[tets[t].first_block + r] = out[r];
  });
}

double worst_strain_limit_violation(const Model& model, const VecX& x) {
  if (!model.has_strain_limits) return -1;
  return overall(model, worst_per_element(model, x, kept_or_thread_local<StrainRowBuffers>(nullptr).worst));
}

}  // namespace sinew
