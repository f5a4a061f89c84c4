// Enumeration of node configurations on a grid under the paper's constraints (Sections 5.1 and 6.3.1),
// labelled by Newton projection.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "dataset/labelled_set.hpp"
#include "geometry/domain.hpp"
#include "projection/newton_projection.hpp"

namespace contactnn::dataset {

/// The grid and the filters. Grid points are the centres of equal cells over the open interval
/// (-limit, limit), so no point lies on an interval end: `n` points give -limit + (2 limit / n)(k + 1/2).
/// Every field is a key of the [gen-configs] config section (configs/bilinear-paper.toml explains each).
struct EnumerationOptions {
  SurfaceKind surface = SurfaceKind::kBilinear;
  geometry::DomainFilters filters;
  int d_xy_points = 20;  ///< grid points per axis for x_D, y_D in (-xy_limit, xy_limit)
  int c_xy_points = 16;  ///< for x_C, y_C
  int c_z_points = 5;    ///< for z_C in (-z_limit, z_limit)
  int s_xy_points = 20;  ///< for x_S, y_S
  int s_z_points = 5;    ///< for z_S
  /// Keep only configurations whose reference projection is inside the segment (status ok). The paper
  /// trains and evaluates on contact points within the segment; rows dropped are still counted.
  bool require_projection_inside = true;
  /// Gregory: node-normal sets per geometric configuration ("twenty different patterns").
  int normal_sets = 20;
  std::uint64_t seed = 1;  ///< Gregory normal sampling; configuration i uses stream (seed, i)
  projection::ProjectionOptions projection;
};

/// What an enumeration did, for the summary gen-configs prints.
struct EnumerationSummary {
  std::int64_t grid_points = 0;     ///< D x C x S grid candidates before any filter
  std::int64_t geometric_kept = 0;  ///< candidates passing the geometric filters (times normal_sets)
  std::int64_t kept = 0;            ///< rows in the dataset
  std::array<std::int64_t, kStatusCount> status_counts{};  ///< over all labelled candidates
  std::array<std::int64_t, 64> iteration_histogram{};      ///< over kept rows; last bin is ">= 63"
  double seconds = 0.0;
};

/// Progress callback: (done, total) labelled candidates; called from one thread, a few times a second.
using ProgressFn = std::function<void(std::int64_t done, std::int64_t total)>;

/// Enumerates, filters and labels. Runs the labelling in parallel (OpenMP); the result is identical for
/// any thread count (rows in grid order, per-row work independent).
[[nodiscard]] LabelledSet enumerate_configurations(const EnumerationOptions& options,
                                                   EnumerationSummary& summary,
                                                   const ProgressFn& progress = {});

/// The grid values for `points` cell centres over (-limit, limit).
[[nodiscard]] std::vector<double> grid_values(double limit, int points);

}  // namespace contactnn::dataset
