// The batch kernel: loss and gradient summed over many patterns, fused and cache-tiled.
//
// Patterns are laid out in panels of kPanelWidth (4 SIMD packets): within a panel each feature's values for
// the panel's patterns are contiguous, so every unit's computation runs across patterns in SIMD. A tile of
// kTilePanels panels goes forward and backward through all layers while its activations stay in L1/L2,
// and its weight gradients are accumulated in per-lane registers, never through a separate big GEMM.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mlp/network.hpp"

namespace contactnn::mlp {

/// SIMD packet of Real chosen by Eigen for the build's instruction set (16 floats with AVX-512).
template <class Real>
using PacketOf = typename Eigen::internal::packet_traits<Real>::type;
template <class Real>
inline constexpr int kLanes = Eigen::internal::unpacket_traits<PacketOf<Real>>::size;
/// Patterns per panel.
template <class Real>
inline constexpr int kPanelWidth = 4 * kLanes<Real>;

/// Patterns in panel layout, grouped into segments (one segment per mini-batch; each segment starts on a
/// panel boundary and its last panel is padded with zero inputs and mask 0).
template <class Real>
class PanelPatterns {
 public:
  struct Segment {
    std::size_t panel_begin = 0, panel_end = 0;  ///< [begin, end) panels
    std::size_t pattern_count = 0;               ///< real (unpadded) patterns
  };

  PanelPatterns(int input_count, int output_count);

  /// Lays out rows order[0..count) of `inputs` (N x n_in) and `targets` (N x n_out), both scaled, in that
  /// order, as segments of `segment_size` patterns (the last one may be shorter; segment_size >= count:
  /// one segment). Buffers only grow: after the first call no further call with the same sizes allocates.
  /// Rows in parallel (OpenMP, `threads`, 0 = OpenMP's default).
  void assign(const MatrixRM<Real>& inputs, const MatrixRM<Real>& targets, const std::uint32_t* order,
              std::size_t count, std::size_t segment_size, int threads = 0);

  [[nodiscard]] int input_count() const { return n_in_; }
  [[nodiscard]] int output_count() const { return n_out_; }
  [[nodiscard]] const std::vector<Segment>& segments() const { return segments_; }
  /// Panel p: n_in x kPanelWidth inputs, n_out x kPanelWidth targets, kPanelWidth mask values (1 or 0).
  /// Consecutive panels are adjacent in memory.
  [[nodiscard]] const Real* inputs(std::size_t panel) const {
    return inputs_.data() + panel * n_in_ * kPanelWidth<Real>;
  }
  [[nodiscard]] const Real* targets(std::size_t panel) const {
    return targets_.data() + panel * n_out_ * kPanelWidth<Real>;
  }
  [[nodiscard]] const Real* mask(std::size_t panel) const { return mask_.data() + panel * kPanelWidth<Real>; }

 private:
  int n_in_, n_out_;
  std::vector<Segment> segments_;
  AlignedVector<Real> inputs_, targets_, mask_;
};

/// Sums of E_p (Eq 14) and of its gradient over one segment. Deterministic for any thread count: a
/// segment's tiles are split into kSlots fixed contiguous ranges, each summed in tile order into its own
/// partial, and the partials are added in slot order; threads only decide who computes which slot.
/// Every buffer is allocated (and first touched by the thread that uses it) in the constructor.
template <class Real>
class BatchGradient {
 public:
  static constexpr int kTilePanels = 4;
  static constexpr int kSlots = 16;

  /// @param threads  OpenMP threads used by compute() and loss(); 0 = OpenMP's default.
  BatchGradient(const Network<Real>& network, int threads = 0);

  /// gradient (network.parameter_count(), parameter layout) = sum over the segment's patterns of dE_p/dw.
  /// @return sum of E_p over the segment.
  double compute(const Network<Real>& network, const PanelPatterns<Real>& patterns, std::size_t segment,
                 Real* gradient);
  /// Sum of E_p over the segment (forward passes only).
  double loss(const Network<Real>& network, const PanelPatterns<Real>& patterns, std::size_t segment);

  [[nodiscard]] int threads() const { return threads_; }

 private:
  struct Workspace {
    AlignedVector<Real> activations;    // layers 1..L, tile-sized
    AlignedVector<Real> deltas;         // layers 1..L, tile-sized
    AlignedVector<Real> lane_gradient;  // parameter_count * kLanes: per-lane gradient sums
  };
  template <bool kBackward>
  double run(const Network<Real>& network, const PanelPatterns<Real>& patterns, std::size_t segment,
             Real* gradient);
  template <bool kBackward>
  Real run_tile(const Network<Real>& network, const PanelPatterns<Real>& patterns, std::size_t panel_begin,
                std::size_t panel_count, bool first, Workspace& ws);

  std::vector<int> sizes_;
  std::size_t parameter_count_;
  int threads_;
  std::vector<std::size_t> layer_offset_;  // offset of layer l (>= 1) in a tile buffer
  std::vector<Workspace> workspaces_;
  AlignedVector<Real> slot_gradient_;  // kSlots x parameter_count
  std::vector<double> slot_loss_;
  std::vector<char> slot_used_;  // a slot with no tile (small segments) contributes nothing
};

}  // namespace contactnn::mlp
