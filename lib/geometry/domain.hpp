// The domain a dataset was generated on and a network was trained on: explicit, recorded with both, and
// checked before a prediction is trusted.
#pragma once

#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::geometry {

/// The geometric filters of the paper's Sections 5.1 and 6.3.1, in the normalised frame (A at the origin,
/// B = (1,0,0), D in the xy-plane). Defaults are the paper's bilinear study. Every field is a key of the
/// [gen-configs] config section with the same name.
struct DomainFilters {
  double xy_limit = 2.0;              ///< |x|, |y| of C, D and S below this ("in the range of (-2.0, 2.0)")
  double z_limit = 0.3;               ///< |z| of C and S below this ("in the range of (-0.3, 0.3)")
  bool ad_not_longer_than_ab = true;  ///< |AD| <= |AB| = 1
  bool nearest_node_a = true;         ///< A is a nearest master node to S
  bool segment_test_a = true;         ///< S passes the segment test of Eqs 3-6 at A
  bool convex = true;                 ///< the segment is strictly convex (seen along the normal at A)
  double min_angle_degrees = 0.0;     ///< every interior angle >= this (Gregory study: 60)
  double max_angle_degrees = 180.0;   ///< every interior angle <= this (Gregory study: 120)
  double max_normal_tilt_tangent = 0.2;  ///< Gregory: tan(angle(node normal, segment's corner normal)) < this

  /// True when the normalised configuration satisfies every filter above. `kind` says whether the node
  /// normals are checked. Coordinate limits are strict, as in the paper's open intervals.
  /// `relative_tolerance` > 0 relaxes every comparison by that fraction of its natural scale (lengths,
  /// 180 degrees for angles), so that a configuration exactly on a filter's boundary (a grid point with
  /// S equidistant from A and B, say) is accepted whatever the rounding of its placement.
  /// `segment_test_tolerance` (< 0: relative_tolerance) is the segment test's (passes_segment_test).
  [[nodiscard]] bool accepts(const geometry::Configuration& normalised, SurfaceKind kind,
                             double relative_tolerance = 0.0, double segment_test_tolerance = -1.0) const;
  /// One line per filter, "key = value", for reports and messages.
  [[nodiscard]] std::string describe() const;
};

/// The domain of a trained network: the generator's filters plus the per-feature range of the dataset
/// it was drawn from. A configuration outside it gets status out_of_domain from evaluate-net.
struct TrainingDomain {
  SurfaceKind surface = SurfaceKind::kBilinear;
  std::vector<double> feature_min;  ///< feature_count(surface) values
  std::vector<double> feature_max;
  DomainFilters filters;

  /// Per-feature range over the rows of `features` (N x F, row-major, contiguous) with status ok, widened
  /// by half the grid step for a feature that takes few distinct values (at most 10000, and each on two
  /// rows or more on average: an enumerated grid, where each value stands for its cell; e.g. y_D in 0.1..0.9
  /// step 0.2 gives [0, 1], so a square segment is in the domain), and by kContinuousWidening of its range
  /// for a continuous one (random sampling, random node normals), whose sample extremes fall just short of
  /// the domain drawn from.
  [[nodiscard]] static TrainingDomain from_features(SurfaceKind kind, const double* features, long rows,
                                                    const std::vector<Status>& status,
                                                    const DomainFilters& filters);
  /// Relative slack of contains(): far above the rounding of raw coordinates mapped into the frame
  /// (~1e-12 for translations of 1e4 element sizes), far below any distance a network could resolve.
  static constexpr double kRelativeTolerance = 1e-9;
  /// Widening of a continuous feature's sample range: above the gap between a sample's extreme and the
  /// domain's (~ range / rows for 1e4+ rows), small enough that the network is not asked to extrapolate.
  static constexpr double kContinuousWidening = 0.01;
  /// True when every feature lies in [min - slack, max + slack] (slack = kRelativeTolerance of the range)
  /// and the filters accept the configuration with kRelativeTolerance (the segment test with
  /// kSegmentTestTolerance, as the global search makes pairs).
  [[nodiscard]] bool contains(const geometry::Configuration& normalised, const double* features) const;
};

}  // namespace contactnn::geometry
