// Internal to lib/search: a network's estimate for the W lanes of a block: the canonical frame and the domain
// test (canonical_frame.h), input scaling, the forward pass of sigmoid units (Eqs 12-13) across the lanes,
// output scaling, and the map back to the caller's node order (SquareSymmetry::to_caller).
#pragma once

#include "search/canonical_frame.h"
#include "search/network_model.hpp"
#include "search/newton_block.hpp"
#include "search/vector_sigmoid.h"

namespace contactnn::search::detail {

template <class Net>
CONTACTNN_SEARCH_INLINE Net sigmoid(Net u, Net gain) {
  if constexpr (sizeof(Net) == sizeof(float)) {
    return cnn_sigmoidf(u, gain);
  } else {
    return cnn_sigmoid(u, gain);
  }
}

/// U consecutive units of a layer for all W lanes: y[u][l] = sum_i w[u][i] x[i][l] - theta[u] (Eq 13). U
/// accumulators of W lanes each stay in registers and run U independent multiply-add chains, so the loop is
/// bound by throughput rather than by the latency of one chain. The loops over lanes carry `omp simd`: left
/// to itself, GCC 12 unrolled and shuffled this nest into 10000 instructions (300 ns a query instead of 16).
template <class Net, int W, int U>
CONTACTNN_SEARCH_INLINE void layer_units(const Net* w, const Net* theta, const Net* x, int n_in, Net* y) {
  Net acc[U][W];
  for (int u = 0; u < U; ++u) {
#pragma omp simd
    for (int l = 0; l < W; ++l) acc[u][l] = -theta[u];
  }
  for (int i = 0; i < n_in; ++i) {
    const Net* xi = x + i * W;
    for (int u = 0; u < U; ++u) {
      const Net wi =
          w[static_cast<std::size_t>(u) * static_cast<std::size_t>(n_in) + static_cast<std::size_t>(i)];
#pragma omp simd
      for (int l = 0; l < W; ++l) acc[u][l] += wi * xi[l];
    }
  }
  for (int u = 0; u < U; ++u) {
#pragma omp simd
    for (int l = 0; l < W; ++l) y[u * W + l] = acc[u][l];
  }
}

/// y[k] = sigmoid(y[k]) for k < n (Eq 12): one flat loop. `omp simd` vectorises it in kernels_single.cpp too
/// (built without auto-vectorisation): a one-lane layer of 32 units is 32 independent sigmoids, and each
/// element rounds as in the scalar loop (no reduction), so a query keeps the same bits alone and in a block.
template <class Net>
static void sigmoid_all(Net* y, int n, Net gain) {
#pragma omp simd
  for (int k = 0; k < n; ++k) y[k] = sigmoid(y[k], gain);
}

/// The affine input features of map_input_features (core/input_features.hpp) for W lanes: the same
/// operations in the same order, so that they round as mlp::predict's. f and g: F x W.
template <int W>
CONTACTNN_SEARCH_INLINE void affine_inputs(const double* f, bool gregory, double* g) {
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const double xd = f[3 * W + l], y = f[4 * W + l];
    const double yd = y < 1e-300 ? 1e-300 : y;  // std::max(y, 1e-300)
    const double rho = std::sqrt(xd * xd + yd * yd);
    const double height = 1.0 / std::sqrt(yd);
    const double beta_c = f[1 * W + l] / yd, beta_s = f[6 * W + l] / yd;
    g[0 * W + l] = f[0 * W + l] - xd * beta_c;
    g[1 * W + l] = beta_c;
    g[2 * W + l] = f[2 * W + l] * height;
    g[3 * W + l] = rho;
    g[4 * W + l] = xd / rho;
    g[5 * W + l] = f[5 * W + l] - xd * beta_s;
    g[6 * W + l] = beta_s;
    g[7 * W + l] = f[7 * W + l] * height;
  }
  if (gregory) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const double xd = f[3 * W + l], y = f[4 * W + l];
      const double yd = y < 1e-300 ? 1e-300 : y;
      const double rho = std::sqrt(xd * xd + yd * yd);
      CONTACTNN_UNROLL
      for (int i = 0; i < 4; ++i) {
        const double p = f[(8 + 2 * i) * W + l], q = f[(9 + 2 * i) * W + l];
        g[(8 + 2 * i) * W + l] = p;
        g[(9 + 2 * i) * W + l] = (p * xd + q * yd) / rho;
      }
    }
  }
}

/// Features f (F x W, canonical order) -> raw outputs out (2 x W, canonical local coordinates): the input map
/// (affine_inputs, when the network has it) and the scaling of mlp::predict (scaled inputs clamped to +-1e6,
/// so any finite feature gives a finite output), then every layer U_j = sum_i W_ji I_i - theta_j, O_j =
/// sigmoid(U_j) in Net, eight units at a time for all lanes.
template <class Net, int W>
static void forward_pass(const NetworkModel& m, const double* f, double* out) {
  alignas(64) Net buffer[2][NetworkModel::kMaxWidth * W];
  const auto& sizes = m.layer_sizes();
  const double* in_min = m.input_min().data();
  const double* in_gain = m.input_gain().data();
  alignas(64) double mapped[16 * W];
  if (m.input_features() == InputFeatures::kAffine) {
    affine_inputs<W>(f, sizes[0] == 16, mapped);
    f = mapped;
  }
  for (int i = 0; i < sizes[0]; ++i) {
    // In the network's type: a float network's inputs are floats (and a float frame's features
    // float-accurate).
    const Net lo = static_cast<Net>(in_min[i]), gain = static_cast<Net>(in_gain[i]);
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      Net x = (static_cast<Net>(f[i * W + l]) - lo) * gain - Net(1);
      x = x > Net(1e6) ? Net(1e6) : x;
      x = x < Net(-1e6) ? Net(-1e6) : x;
      buffer[0][i * W + l] = x;
    }
  }
  const Net gain = m.gain<Net>();
  int current = 0;
  for (int layer = 0; layer < m.layer_count(); ++layer) {
    const int n_in = sizes[static_cast<std::size_t>(layer)],
              n_out = sizes[static_cast<std::size_t>(layer) + 1];
    const Net* weights = m.parameters<Net>() + m.weight_offset(layer);
    const Net* thresholds = weights + static_cast<std::size_t>(n_out) * static_cast<std::size_t>(n_in);
    const Net* x = buffer[current];
    Net* y = buffer[1 - current];
    if constexpr (W == 1) {
      // One query: the layer across its units, kUnitGroup at a time in registers (W_l transposed and padded),
      // each unit's chain -theta + w_0 x_0 + w_1 x_1 + ... as layer_units runs it for a lane, so the same
      // bits. layer_units with one lane ran 8 chains of scalar multiply-adds (gregory-48: half a one-query
      // call).
      constexpr int G = NetworkModel::kUnitGroup;
      const Net* wt = m.transposed_weights<Net>(layer);
      const auto stride = static_cast<std::size_t>(m.padded_units(layer));
      const Net* theta = wt + static_cast<std::size_t>(n_in) * stride;
      for (int j0 = 0; j0 < n_out; j0 += G) {
        Net acc[G];
#pragma omp simd
        for (int k = 0; k < G; ++k) acc[k] = -theta[j0 + k];
        for (int i = 0; i < n_in; ++i) {
          const Net xi = x[i];
          const Net* row = wt + static_cast<std::size_t>(i) * stride + static_cast<std::size_t>(j0);
#pragma omp simd
          for (int k = 0; k < G; ++k) acc[k] += row[k] * xi;
        }
        // The padding units land in y past n_out (the buffer holds kMaxWidth, a multiple of G) and are never
        // read.
#pragma omp simd
        for (int k = 0; k < G; ++k) y[j0 + k] = acc[k];
      }
      sigmoid_all(y, n_out, gain);
      current = 1 - current;
      continue;
    }
    const auto row = [&](int j) {
      return weights + static_cast<std::size_t>(j) * static_cast<std::size_t>(n_in);
    };
    int j = 0;
    for (; j + 8 <= n_out; j += 8) layer_units<Net, W, 8>(row(j), thresholds + j, x, n_in, y + j * W);
    if (j + 4 <= n_out) {
      layer_units<Net, W, 4>(row(j), thresholds + j, x, n_in, y + j * W);
      j += 4;
    }
    if (j + 2 <= n_out) {
      layer_units<Net, W, 2>(row(j), thresholds + j, x, n_in, y + j * W);
      j += 2;
    }
    if (j < n_out) layer_units<Net, W, 1>(row(j), thresholds + j, x, n_in, y + j * W);
    sigmoid_all(y, n_out * W, gain);
    current = 1 - current;
  }
  const double low = m.target_low();
  for (int k = 0; k < 2; ++k) {
    const double lo = m.output_min()[static_cast<std::size_t>(k)];
    const double inv_gain = m.output_inverse_gain()[static_cast<std::size_t>(k)];
    for (int l = 0; l < W; ++l)
      out[k * W + l] = lo + (static_cast<double>(buffer[current][k * W + l]) - low) * inv_gain;
  }
}

/// The estimate of a lane on a tie (cnn_cf_needs_forms): the mean over its canonical forms (cnn_cf_forms) in
/// the domain of the network's prediction mapped to the caller's order, status ok; when no form is in the
/// domain, the mean over every form, status out_of_domain. Without check_domain every form counts as in the
/// domain. `query`: the lane's 15 or 27 raw values, contiguous. Defined once, in kernels_single.cpp (compiled
/// without auto-vectorisation), so that a query gives the same bits in a block of any width.
template <class Net, bool kGregory>
void tie_estimate(const NetworkModel& m, bool check_domain, const double* query, double& u, double& v,
                  double& status);

/// Whether the labels call query `query` (15 or 27 raw values, finite) degenerate, as
/// dataset::label_configuration decides: no canonical frame at any corner (geometry::normalise) or a
/// collapsed segment (geometry::is_degenerate_segment). The network's own frame has no fallback corner, so a
/// query it cannot canonicalise may still have a label. Defined in kernels_single.cpp; scalar, for the rare
/// lanes that need it.
bool degenerate_as_labelled(const double* query, bool gregory);

/// Forms 0 .. count - 1 of tie lanes (count <= CW): lane owner[i] of `raw` (a block of W lanes) with symmetry
/// sym[i] and z orientation z[i] forced, through cnn_cf_lane, the domain test and the forward pass in a block
/// of CW forms (the empty slots copies of the first). Writes each form's prediction in the caller's order (x,
/// y), whether the form exists (valid) and whether it lies in the domain (inside).
template <class Net, int CW, int W, bool kGregory>
static void predict_forms(const NetworkModel& m, bool check_domain, const double* raw, const int* owner,
                          const int* sym, const int* z, int count, double* x, double* y, bool* valid,
                          bool* inside) {
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr int kG = kGregory ? 1 : 0;
  alignas(64) double in[27 * CW], features[16 * CW], normals[12 * CW], info[CNN_CF_INFO_ROWS * CW],
      out[2 * CW];
  int form_sym[CW], form_z[CW];
  for (int slot = 0; slot < CW; ++slot) {
    const int from = slot < count ? slot : 0;
    for (int k = 0; k < kStride; ++k) in[k * CW + slot] = raw[k * W + owner[from]];
    form_sym[slot] = sym[from];
    form_z[slot] = z[from];
  }
  CNN_CF_IVDEP
  for (int slot = 0; slot < CW; ++slot) {
    cnn_cf_lane(in + slot, CW, kG, 1, form_sym[slot], form_z[slot], features + slot, normals + slot,
                info + slot, CW);
  }
  for (int slot = 0; slot < count; ++slot) {
    if (info[4 * CW + slot] != 0.0) {
      cnn_cf_lane_scaled(in + slot, CW, kG, 1, form_sym[slot], form_z[slot], features + slot, normals + slot,
                         info + slot, CW);
    }
    valid[slot] = info[slot] == kOk;  // cnn_cf_forms keeps the forms that exist
  }
  if (check_domain) cnn_domain_block(CW, kG, &m.domain_bounds(), features, normals, info);
  forward_pass<Net, CW>(m, features, out);
  for (int slot = 0; slot < count; ++slot) {
    x[slot] = out[slot];
    y[slot] = out[CW + slot];
    cnn_cf_to_caller(info[CW + slot], kGregory ? 0.5 : 0.0, &x[slot], &y[slot]);
    inside[slot] = info[slot] == kOk;
  }
}

/// The lanes of a block on a tie, W > 1: tie_estimate's answers. A lane's form 0 is the block's own (its
/// features, domain status and prediction are already in the block); its other forms (one per symmetry of
/// cnn_cf_symmetries and, Gregory on a z tie, each orientation of z, in cnn_cf_forms' order) go through
/// predict_forms, the forms of all the tie lanes one after another, W at a time and the rest 8 at a time (a
/// block of real decks' pairs has a few tie lanes, two forms each: a block of W forms for them cost more than
/// the rest of the block). Each lane's predictions are summed in the order of its forms, as tie_estimate sums
/// them, and every step is the one the one-lane path takes, so the bits are the same (tested against a query
/// alone).
template <class Net, int W, bool kGregory>
static void tie_estimates_block(const NetworkModel& m, bool check_domain, const double* raw,
                                const double* info, const int* lanes, int n_lanes, LaneState<W>& s) {
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr int kMaxForms = 16 * W;  // 8 symmetries x 2 orientations of z per lane, at most
  constexpr int kNarrow = W < 8 ? W : 8;
  int owner[kMaxForms], form_sym[kMaxForms], form_z[kMaxForms];
  double x[kMaxForms], y[kMaxForms];
  bool valid[kMaxForms], inside_form[kMaxForms];
  int count = 0;
  for (int t = 0; t < n_lanes; ++t) {
    const int l = lanes[t];
    double query[27];
    for (int k = 0; k < kStride; ++k) query[k] = raw[k * W + l];
    int sym[8];
    const int tied = cnn_cf_symmetries(query, sym);
    const int sym0 = static_cast<int>(info[W + l]);
    const int z_ties = (kGregory ? 1 : 0) & (static_cast<int>(info[5 * W + l]) >> 1);
    for (int k = 0; k < tied; ++k) {
      for (int z = 0; z <= z_ties; ++z) {
        if (sym[k] == sym0 && z == 0) continue;  // form 0
        owner[count] = l;
        form_sym[count] = sym[k];
        form_z[count] = z;
        ++count;
      }
    }
  }
  int done = 0;
  for (; count - done >= W; done += W) {
    predict_forms<Net, W, W, kGregory>(m, check_domain, raw, owner + done, form_sym + done, form_z + done, W,
                                       x + done, y + done, valid + done, inside_form + done);
  }
  for (; done < count; done += kNarrow) {
    const int n = count - done < kNarrow ? count - done : kNarrow;
    predict_forms<Net, kNarrow, W, kGregory>(m, check_domain, raw, owner + done, form_sym + done,
                                             form_z + done, n, x + done, y + done, valid + done,
                                             inside_form + done);
  }
  // Per tie lane, in the order of its forms: the sums over every form and over the forms in the domain. Form
  // 0: the block's (0.0 + x: tie_estimate's sums start from 0.0, which turns a -0 into +0).
  double all_u[W], all_v[W], forms_of[W], in_u[W], in_v[W], inside[W];
  for (int t = 0; t < n_lanes; ++t) {
    const int l = lanes[t];
    const bool in_domain = info[l] == kOk;
    all_u[l] = 0.0 + s.u[l];
    all_v[l] = 0.0 + s.v[l];
    forms_of[l] = 1.0;
    in_u[l] = 0.0 + (in_domain ? s.u[l] : 0.0);
    in_v[l] = 0.0 + (in_domain ? s.v[l] : 0.0);
    inside[l] = in_domain ? 1.0 : 0.0;
  }
  for (int i = 0; i < count; ++i) {
    if (!valid[i]) continue;
    const int l = owner[i];
    all_u[l] += x[i];
    all_v[l] += y[i];
    forms_of[l] += 1.0;
    in_u[l] += inside_form[i] ? x[i] : 0.0;
    in_v[l] += inside_form[i] ? y[i] : 0.0;
    inside[l] += inside_form[i] ? 1.0 : 0.0;
  }
  for (int t = 0; t < n_lanes; ++t) {
    const int l = lanes[t];
    const bool any = inside[l] > 0.0;
    s.u[l] = any ? in_u[l] / inside[l] : all_u[l] / forms_of[l];
    s.v[l] = any ? in_v[l] / inside[l] : all_v[l] / forms_of[l];
    s.status[l] = any ? kOk : kOutOfDomain;
  }
}

/// How a float network's bilinear block gets its canonical frame and domain test (canonical_frame.h):
/// kFloat, in float where float decides them and in double for the other lanes of the block; kFloatDeferred,
/// the same, but where few lanes of the block are undecided those get status kPending (LocalSearch::run
/// computes them again, gathered from many blocks, with kDouble); kDouble, in double. Every pass gives a lane
/// the same bits: a lane float decides has its float features in each of the first two, and the others their
/// double ones. Double networks and Gregory patches: always in double.
enum class FramePass { kFloat, kFloatDeferred, kDouble };

/// The network's estimate for every lane of a raw block (`raw`: 15 or 27 rows of W, world coordinates), in
/// the caller's node order: status ok, out_of_domain (with check_domain), degenerate or invalid; the estimate
/// is the domain centre for the last two. Lanes on a tie are redone after the block: tie_estimate for a block
/// of one lane, tie_estimates_block for wider blocks.
template <class Net, int W, bool kGregory>
static void network_estimate(const NetworkModel& m, bool check_domain, const double* raw, LaneState<W>& s,
                             FramePass pass = FramePass::kFloat) {
  alignas(64) double features[16 * W], normals[12 * W], info[CNN_CF_INFO_ROWS * W], out[2 * W];
  constexpr int kG = kGregory ? 1 : 0;
  const cnn_domain* domain = check_domain ? &m.domain_bounds() : nullptr;
  bool deferred = false, framed = false;
  if constexpr (!kGregory && sizeof(Net) == sizeof(float)) {
    // A float network: the frame and the domain test in float where float decides them (canonical_frame.h).
    if (pass != FramePass::kDouble && cnn_cff_applies(W, domain)) {
      framed = true;
      // Real decks' pairs leave every lane to the double pass (touching contact, square elements; six
      // CalculiX decks, bilinear-8, batched, 1 thread: 108 ns per query with the float pass first, 77 with
      // the double pass alone): after a block with many such lanes this thread runs the double pass first
      // (cnn_cff_block_expecting). The expectation changes the speed only, never a result.
      thread_local int expect_undecided = 0;
      const int undecided = cnn_cff_block_expecting(W, domain, raw, features, info, &expect_undecided);
      // A few undecided lanes (random queries of the paper's domain: 2 in 100): pending with kFloatDeferred,
      // as a double pass for one or two lanes of a block costs more than gathering them from many blocks.
      // Many (the decks above): redone here, as a lane left pending costs this block's forward pass, a second
      // load and a second forward pass (127 ns per query on the decks).
      if (undecided > 0 && pass == FramePass::kFloatDeferred && undecided * CNN_CFF_MANY_UNDECIDED < W) {
        deferred = true;
      } else if (undecided > 0) {
        cnn_cff_redo(W, domain, raw, features, info);
      }
    }
  }
  if (!framed) {
    cnn_canonicalise_block(W, kG, raw, features, normals, info);
    if (check_domain) cnn_domain_block(W, kG, domain, features, normals, info);
  }
  forward_pass<Net, W>(m, features, out);
  const double centre = kGregory ? 0.5 : 0.0;
  int ties = 0;
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const double status = info[l];
    double x = out[l], y = out[W + l];
    cnn_cf_to_caller(info[W + l], centre, &x, &y);
    const bool usable = (status == kOk) | (status == kOutOfDomain);
    s.u[l] = usable ? x : centre;
    s.v[l] = usable ? y : centre;
    s.status[l] = status;
    s.iterations[l] = 0.0;
  }
  if (deferred) {
    // The lanes the float pass left undecided: pending, for LocalSearch::run's double pass
    // (FramePass::kDouble).
    for (int l = 0; l < W; ++l) {
      const bool pending = info[4 * W + l] != 0.0;
      s.u[l] = pending ? centre : s.u[l];
      s.v[l] = pending ? centre : s.v[l];
      s.status[l] = pending ? kPending : s.status[l];  // cnn_cff_block gave them tie code 0: no forms below
    }
  }
  for (int l = 0; l < W; ++l)
    ties |= cnn_cf_needs_forms(info[5 * W + l], kG) & (info[l] == kOk || info[l] == kOutOfDomain);
  if (ties == 0) return;
  if constexpr (W == 1) {
    constexpr int kStride = kGregory ? 27 : 15;
    double query[27];
    for (int k = 0; k < kStride; ++k) query[k] = raw[k];
    tie_estimate<Net, kGregory>(m, check_domain, query, s.u[0], s.v[0], s.status[0]);
  } else {
    int lanes[W], n_lanes = 0;
    for (int l = 0; l < W; ++l) {
      if (cnn_cf_needs_forms(info[5 * W + l], kG) && (info[l] == kOk || info[l] == kOutOfDomain))
        lanes[n_lanes++] = l;
    }
    tie_estimates_block<Net, W, kGregory>(m, check_domain, raw, info, lanes, n_lanes, s);
  }
}

}  // namespace contactnn::search::detail
