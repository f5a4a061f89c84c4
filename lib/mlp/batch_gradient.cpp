#include "mlp/batch_gradient.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <new>

#include "core/error.hpp"
#include "mlp/activation.hpp"
#include "mlp/flush_denormals.hpp"

namespace contactnn::mlp {

namespace {

using Eigen::internal::padd;
using Eigen::internal::pload;
using Eigen::internal::pmadd;
using Eigen::internal::pmul;
using Eigen::internal::predux;
using Eigen::internal::pset1;
using Eigen::internal::pstore;
using Eigen::internal::psub;

// Register blocking sized to the SIMD register file: the unit-by-panel kernel keeps kRowBlock x 4 packet
// accumulators, 4 input packets and one broadcast live; the gradient kernel kGradRows x kGradCols
// accumulators plus one packet per row and column.
constexpr int kRegisters = EIGEN_ARCH_DEFAULT_NUMBER_OF_REGISTERS;
constexpr int kRowBlock = kRegisters >= 32 ? 6 : 2;
constexpr int kGradRows = kRegisters >= 32 ? 4 : 2;
constexpr int kGradCols = kRegisters >= 32 ? 4 : 3;

// Unit rows r0 .. r0+JB-1 of one panel: acc[r] = init(r) + sum_idx W(r, idx) src[idx][:], then finish(r,
// acc). Forward (Eq 13): W(r, idx) = W_l[r][idx], src = the layer below. Back-propagation: W(r, idx) =
// W_l[idx][r] (the transpose), src = the deltas of the layer above. Strides select which.
template <class Real, int JB, class Init, class Finish>
inline void unit_rows(const Real* w, std::size_t stride_r, std::size_t stride_idx, int count, const Real* src,
                      int r0, const Init& init, const Finish& finish) {
  using P = PacketOf<Real>;
  constexpr int L = kLanes<Real>;
  constexpr int PW = kPanelWidth<Real>;
  P acc[JB][4];
  for (int r = 0; r < JB; ++r) {
    const P start = init(r0 + r);
    for (int q = 0; q < 4; ++q) acc[r][q] = start;
  }
  const Real* wr = w + static_cast<std::size_t>(r0) * stride_r;
  for (int idx = 0; idx < count; ++idx) {
    const Real* s = src + static_cast<std::size_t>(idx) * PW;
    const P x0 = pload<P>(s), x1 = pload<P>(s + L), x2 = pload<P>(s + 2 * L), x3 = pload<P>(s + 3 * L);
    const Real* wi = wr + static_cast<std::size_t>(idx) * stride_idx;
    for (int r = 0; r < JB; ++r) {
      const P wv = pset1<P>(wi[static_cast<std::size_t>(r) * stride_r]);
      acc[r][0] = pmadd(wv, x0, acc[r][0]);
      acc[r][1] = pmadd(wv, x1, acc[r][1]);
      acc[r][2] = pmadd(wv, x2, acc[r][2]);
      acc[r][3] = pmadd(wv, x3, acc[r][3]);
    }
  }
  for (int r = 0; r < JB; ++r) finish(r0 + r, acc[r]);
}

template <class Real, int JB, class Init, class Finish>
inline void unit_rows_remainder(int rem, const Real* w, std::size_t stride_r, std::size_t stride_idx,
                                int count, const Real* src, int r0, const Init& init, const Finish& finish) {
  if constexpr (JB > 0) {
    if (rem == JB) {
      unit_rows<Real, JB>(w, stride_r, stride_idx, count, src, r0, init, finish);
    } else {
      unit_rows_remainder<Real, JB - 1>(rem, w, stride_r, stride_idx, count, src, r0, init, finish);
    }
  }
}

// All `rows` units of one panel, in blocks of kRowBlock.
template <class Real, class Init, class Finish>
inline void all_unit_rows(int rows, const Real* w, std::size_t stride_r, std::size_t stride_idx, int count,
                          const Real* src, const Init& init, const Finish& finish) {
  int r0 = 0;
  for (; r0 + kRowBlock <= rows; r0 += kRowBlock) {
    unit_rows<Real, kRowBlock>(w, stride_r, stride_idx, count, src, r0, init, finish);
  }
  unit_rows_remainder<Real, kRowBlock - 1>(rows - r0, w, stride_r, stride_idx, count, src, r0, init, finish);
}

// Per-lane weight-gradient sums over a tile: G[j][i] += sum_panels delta[j][:] * act[i][:] for a block of
// JB x IB (j, i), accumulators in registers for the whole tile.
template <class Real, int JB, int IB>
inline void gradient_block(const Real* delta, const Real* act, int n_out, int n_in, int j0, int i0,
                           int panels, bool first, Real* lane_gradient) {
  using P = PacketOf<Real>;
  constexpr int L = kLanes<Real>;
  constexpr int PW = kPanelWidth<Real>;
  P acc[JB][IB];
  for (int r = 0; r < JB; ++r)
    for (int c = 0; c < IB; ++c)
      acc[r][c] = first ? pset1<P>(Real(0))
                        : pload<P>(lane_gradient + (static_cast<std::size_t>(j0 + r) * n_in + i0 + c) * L);
  for (int k = 0; k < panels; ++k) {
    const Real* d = delta + static_cast<std::size_t>(k) * n_out * PW + static_cast<std::size_t>(j0) * PW;
    const Real* a = act + static_cast<std::size_t>(k) * n_in * PW + static_cast<std::size_t>(i0) * PW;
    for (int q = 0; q < 4; ++q) {
      P dv[JB], av[IB];
      for (int r = 0; r < JB; ++r) dv[r] = pload<P>(d + r * PW + q * L);
      for (int c = 0; c < IB; ++c) av[c] = pload<P>(a + c * PW + q * L);
      for (int r = 0; r < JB; ++r)
        for (int c = 0; c < IB; ++c) acc[r][c] = pmadd(dv[r], av[c], acc[r][c]);
    }
  }
  for (int r = 0; r < JB; ++r)
    for (int c = 0; c < IB; ++c)
      pstore(lane_gradient + (static_cast<std::size_t>(j0 + r) * n_in + i0 + c) * L, acc[r][c]);
}

template <class Real, int JB, int IB>
inline void gradient_block_cols(int ib, const Real* delta, const Real* act, int n_out, int n_in, int j0,
                                int i0, int panels, bool first, Real* g) {
  if constexpr (IB > 0) {
    if (ib == IB) {
      gradient_block<Real, JB, IB>(delta, act, n_out, n_in, j0, i0, panels, first, g);
    } else {
      gradient_block_cols<Real, JB, IB - 1>(ib, delta, act, n_out, n_in, j0, i0, panels, first, g);
    }
  }
}

template <class Real, int JB>
inline void gradient_block_any(int jb, int ib, const Real* delta, const Real* act, int n_out, int n_in,
                               int j0, int i0, int panels, bool first, Real* g) {
  if constexpr (JB > 0) {
    if (jb == JB) {
      gradient_block_cols<Real, JB, kGradCols>(ib, delta, act, n_out, n_in, j0, i0, panels, first, g);
    } else {
      gradient_block_any<Real, JB - 1>(jb, ib, delta, act, n_out, n_in, j0, i0, panels, first, g);
    }
  }
}

}  // namespace

template <class Real>
PanelPatterns<Real>::PanelPatterns(int input_count, int output_count)
    : n_in_(input_count), n_out_(output_count) {
  CONTACTNN_REQUIRE(input_count >= 1 && output_count >= 1,
                    "panel layout needs inputs and outputs, got " << input_count << " and " << output_count);
}

template <class Real>
void PanelPatterns<Real>::assign(const MatrixRM<Real>& inputs, const MatrixRM<Real>& targets,
                                 const std::uint32_t* order, std::size_t count, std::size_t segment_size,
                                 int threads) {
  constexpr int PW = kPanelWidth<Real>;
  CONTACTNN_REQUIRE(inputs.cols() == n_in_ && targets.cols() == n_out_ && inputs.rows() == targets.rows(),
                    "panel layout: expected N x " << n_in_ << " inputs and N x " << n_out_ << " targets, got "
                                                  << inputs.rows() << " x " << inputs.cols() << " and "
                                                  << targets.rows() << " x " << targets.cols());
  CONTACTNN_REQUIRE(
      count >= 1 && segment_size >= 1,
      "panel layout needs patterns and a positive segment size, got " << count << " and " << segment_size);
  segments_.clear();
  std::size_t panels = 0;
  for (std::size_t start = 0; start < count; start += segment_size) {
    const std::size_t n = std::min(segment_size, count - start);
    const std::size_t seg_panels = (n + PW - 1) / PW;
    segments_.push_back({panels, panels + seg_panels, n});
    panels += seg_panels;
  }
  if (inputs_.size() < panels * n_in_ * PW) inputs_.resize(panels * n_in_ * PW);
  if (targets_.size() < panels * n_out_ * PW) targets_.resize(panels * n_out_ * PW);
  if (mask_.size() < panels * PW) mask_.resize(panels * PW);
  const auto n_segments = static_cast<std::ptrdiff_t>(segments_.size());
  const int n_threads = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for num_threads(n_threads) schedule(static)
  for (std::ptrdiff_t s = 0; s < n_segments; ++s) {
    const Segment& seg = segments_[s];
    const std::size_t first_pattern = static_cast<std::size_t>(s) * segment_size;
    for (std::size_t p = seg.panel_begin; p < seg.panel_end; ++p) {
      Real* in = inputs_.data() + p * n_in_ * PW;
      Real* tg = targets_.data() + p * n_out_ * PW;
      Real* m = mask_.data() + p * PW;
      const std::size_t base = first_pattern + (p - seg.panel_begin) * PW;
      for (int lane = 0; lane < PW; ++lane) {
        // Shuffled rows are scattered over more than L2: fetch a few patterns ahead.
        constexpr int kAhead = 8;
        if ((p - seg.panel_begin) * PW + lane + kAhead < seg.pattern_count) {
          const std::size_t ahead = order[base + lane + kAhead];
          __builtin_prefetch(inputs.data() + ahead * n_in_);
          __builtin_prefetch(targets.data() + ahead * n_out_);
        }
        const bool real = (p - seg.panel_begin) * PW + lane < seg.pattern_count;
        const Real* x = real ? inputs.data() + static_cast<std::size_t>(order[base + lane]) * n_in_ : nullptr;
        const Real* t =
            real ? targets.data() + static_cast<std::size_t>(order[base + lane]) * n_out_ : nullptr;
        for (int i = 0; i < n_in_; ++i) in[i * PW + lane] = real ? x[i] : Real(0);
        for (int k = 0; k < n_out_; ++k) tg[k * PW + lane] = real ? t[k] : Real(0);
        m[lane] = real ? Real(1) : Real(0);
      }
    }
  }
}

template <class Real>
BatchGradient<Real>::BatchGradient(const Network<Real>& network, int threads)
    : sizes_(network.layer_sizes()),
      parameter_count_(network.parameter_count()),
      threads_(threads > 0 ? threads : omp_get_max_threads()) {
  constexpr int PW = kPanelWidth<Real>;
  std::size_t tile_units = 0;
  layer_offset_.assign(sizes_.size(), 0);
  for (std::size_t l = 1; l < sizes_.size(); ++l) {
    layer_offset_[l] = tile_units;
    tile_units += static_cast<std::size_t>(sizes_[l]) * kTilePanels * PW;
  }
  workspaces_.resize(static_cast<std::size_t>(threads_));
  // Each thread allocates and zeroes its own workspace: first touch places the pages near it, and no
  // page is touched for the first time inside an epoch.
  // An exception cannot leave an OpenMP region (it would terminate the process): a failed allocation is
  // noted and thrown once the threads have joined, so the caller can report "out of memory".
  std::atomic<bool> out_of_memory{false};
#pragma omp parallel num_threads(threads_)
  {
    const int t = omp_get_thread_num();
    Workspace& ws = workspaces_[static_cast<std::size_t>(t)];
    try {
      ws.activations.assign(tile_units, Real(0));
      ws.deltas.assign(tile_units, Real(0));
      ws.lane_gradient.assign(parameter_count_ * kLanes<Real>, Real(0));
    } catch (const std::bad_alloc&) {
      out_of_memory = true;
    }
  }
  if (out_of_memory) throw std::bad_alloc();
  slot_gradient_.assign(static_cast<std::size_t>(kSlots) * parameter_count_, Real(0));
  slot_loss_.assign(kSlots, 0.0);
  slot_used_.assign(kSlots, 0);
}

template <class Real>
double BatchGradient<Real>::compute(const Network<Real>& network, const PanelPatterns<Real>& patterns,
                                    std::size_t segment, Real* gradient) {
  return run<true>(network, patterns, segment, gradient);
}

template <class Real>
double BatchGradient<Real>::loss(const Network<Real>& network, const PanelPatterns<Real>& patterns,
                                 std::size_t segment) {
  return run<false>(network, patterns, segment, nullptr);
}

template <class Real>
template <bool kBackward>
double BatchGradient<Real>::run(const Network<Real>& network, const PanelPatterns<Real>& patterns,
                                std::size_t segment, Real* gradient) {
  CONTACTNN_REQUIRE(network.layer_sizes() == sizes_, "batch kernel built for another architecture");
  CONTACTNN_REQUIRE(patterns.input_count() == sizes_.front() && patterns.output_count() == sizes_.back(),
                    "batch kernel: patterns have " << patterns.input_count() << " inputs and "
                                                   << patterns.output_count() << " outputs, the network "
                                                   << sizes_.front() << " and " << sizes_.back());
  CONTACTNN_REQUIRE(segment < patterns.segments().size(),
                    "segment " << segment << " of " << patterns.segments().size());
  const auto& seg = patterns.segments()[segment];
  const std::size_t n_tiles = (seg.panel_end - seg.panel_begin + kTilePanels - 1) / kTilePanels;
  const std::size_t P = parameter_count_;
  constexpr int L = kLanes<Real>;
  // No more threads than tiles: a small segment (a validation set, a mini-batch) does not pay for waking
  // threads with nothing to do. The slots, and so the result, do not depend on it.
  const int active = static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(threads_), std::max<std::size_t>(n_tiles, 1)));
#pragma omp parallel for num_threads(active) schedule(static)
  for (int s = 0; s < kSlots; ++s) {
    const ScopedFlushDenormals flush;  // per thread: MXCSR is thread state
    Workspace& ws = workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
    const std::size_t tile_begin = n_tiles * s / kSlots;
    const std::size_t tile_end = n_tiles * (s + 1) / kSlots;
    slot_used_[s] = tile_end > tile_begin;
    double slot_loss = 0.0;
    for (std::size_t t = tile_begin; t < tile_end; ++t) {
      const std::size_t panel = seg.panel_begin + t * kTilePanels;
      const std::size_t count = std::min<std::size_t>(kTilePanels, seg.panel_end - panel);
      // The slot's first tile starts the per-lane sums at zero: no separate clearing pass.
      slot_loss +=
          static_cast<double>(run_tile<kBackward>(network, patterns, panel, count, t == tile_begin, ws));
    }
    slot_loss_[s] = slot_loss;
    if (kBackward && slot_used_[s]) {
      Real* out = slot_gradient_.data() + static_cast<std::size_t>(s) * P;
      const Real* lanes = ws.lane_gradient.data();
      for (std::size_t p = 0; p < P; ++p) out[p] = predux(pload<PacketOf<Real>>(lanes + p * L));
      // The lanes summed dE/dU_j for thresholds; dE/dtheta_j = -dE/dU_j (Eq 13).
      for (int l = 0; l + 1 < static_cast<int>(sizes_.size()); ++l) {
        const std::size_t off = network.threshold_offset(l);
        for (int j = 0; j < sizes_[l + 1]; ++j) out[off + j] = -out[off + j];
      }
    }
  }
  double total = 0.0;
  for (int s = 0; s < kSlots; ++s) total += slot_loss_[s];
  if (kBackward) {
    for (std::size_t p = 0; p < P; ++p) {
      double sum = 0.0;
      for (int s = 0; s < kSlots; ++s) {
        if (slot_used_[s]) sum += static_cast<double>(slot_gradient_[static_cast<std::size_t>(s) * P + p]);
      }
      gradient[p] = static_cast<Real>(sum);
    }
  }
  return total;
}

template <class Real>
template <bool kBackward>
Real BatchGradient<Real>::run_tile(const Network<Real>& network, const PanelPatterns<Real>& patterns,
                                   std::size_t panel_begin, std::size_t panel_count, bool first,
                                   Workspace& ws) {
  using P = PacketOf<Real>;
  constexpr int L = kLanes<Real>;
  constexpr int PW = kPanelWidth<Real>;
  const int n_layers = static_cast<int>(sizes_.size()) - 1;
  const P gain = pset1<P>(network.gain());
  const P one = pset1<P>(Real(1));
  const P zero = pset1<P>(Real(0));
  auto act = [&](int l, std::size_t k) -> Real* {
    return ws.activations.data() + layer_offset_[l] + k * static_cast<std::size_t>(sizes_[l]) * PW;
  };
  auto del = [&](int l, std::size_t k) -> Real* {
    return ws.deltas.data() + layer_offset_[l] + k * static_cast<std::size_t>(sizes_[l]) * PW;
  };
  P loss = zero;
  for (std::size_t k = 0; k < panel_count; ++k) {
    // Forward (Eqs 12-13), unit blocks across the panel's patterns.
    for (int l = 0; l < n_layers; ++l) {
      const int n_in = sizes_[l];
      const Real* src = l == 0 ? patterns.inputs(panel_begin + k) : act(l, k);
      Real* dst = act(l + 1, k);
      const Real* theta = network.thresholds(l);
      all_unit_rows<Real>(
          sizes_[l + 1], network.weights(l), static_cast<std::size_t>(n_in), 1, n_in, src,
          [&](int j) { return pset1<P>(-theta[j]); },
          [&](int j, const P* u) {
            for (int q = 0; q < 4; ++q) pstore(dst + j * PW + q * L, sigmoid_packet(u[q], gain));
          });
    }
    // Output error (Eq 14) and output deltas dE/dU = (O - T) gain O (1 - O); padding has mask 0.
    const Real* o = act(n_layers, k);
    const Real* t = patterns.targets(panel_begin + k);
    const Real* m = patterns.mask(panel_begin + k);
    Real* d_out = del(n_layers, k);
    for (int j = 0; j < sizes_.back(); ++j) {
      for (int q = 0; q < 4; ++q) {
        const P ov = pload<P>(o + j * PW + q * L);
        const P e = pmul(pload<P>(m + q * L), psub(ov, pload<P>(t + j * PW + q * L)));
        loss = pmadd(e, e, loss);
        if (kBackward) pstore(d_out + j * PW + q * L, pmul(pmul(e, gain), pmul(ov, psub(one, ov))));
      }
    }
    if (!kBackward) continue;
    // Back-propagation: delta_l = gain a_l (1 - a_l) * W_l^T delta_{l+1}.
    for (int l = n_layers - 1; l >= 1; --l) {
      const int n_here = sizes_[l];
      const Real* a = act(l, k);
      Real* d_here = del(l, k);
      all_unit_rows<Real>(
          n_here, network.weights(l), 1, static_cast<std::size_t>(n_here), sizes_[l + 1], del(l + 1, k),
          [&](int) { return zero; },
          [&](int i, const P* s) {
            for (int q = 0; q < 4; ++q) {
              const P av = pload<P>(a + i * PW + q * L);
              pstore(d_here + i * PW + q * L, pmul(s[q], pmul(gain, pmul(av, psub(one, av)))));
            }
          });
    }
  }
  if (kBackward) {
    // Weight gradients of the tile: dE/dW_ji = sum_p delta_j I_i, per lane.
    const int panels = static_cast<int>(panel_count);
    for (int l = 0; l < n_layers; ++l) {
      const int n_in = sizes_[l];
      const int n_out = sizes_[l + 1];
      const Real* below = l == 0 ? patterns.inputs(panel_begin) : act(l, 0);
      const Real* d = del(l + 1, 0);
      Real* g = ws.lane_gradient.data() + network.weight_offset(l) * L;
      for (int j0 = 0; j0 < n_out; j0 += kGradRows) {
        const int jb = std::min(kGradRows, n_out - j0);
        for (int i0 = 0; i0 < n_in; i0 += kGradCols) {
          gradient_block_any<Real, kGradRows>(jb, std::min(kGradCols, n_in - i0), d, below, n_out, n_in, j0,
                                              i0, panels, first, g);
        }
      }
      Real* gt = ws.lane_gradient.data() + network.threshold_offset(l) * L;
      for (int j = 0; j < n_out; ++j) {
        P acc = first ? pset1<P>(Real(0)) : pload<P>(gt + j * L);
        for (int kk = 0; kk < panels; ++kk) {
          const Real* dj = d + static_cast<std::size_t>(kk) * n_out * PW + j * PW;
          acc = padd(acc, padd(padd(pload<P>(dj), pload<P>(dj + L)),
                               padd(pload<P>(dj + 2 * L), pload<P>(dj + 3 * L))));
        }
        pstore(gt + j * L, acc);
      }
    }
  }
  return Real(0.5) * predux(loss);
}

template class PanelPatterns<float>;
template class PanelPatterns<double>;
template class BatchGradient<float>;
template class BatchGradient<double>;

}  // namespace contactnn::mlp
