#include "dataset/enumeration.hpp"

#include <omp.h>

#include <atomic>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "dataset/progress_counter.hpp"
#include "dataset/random_stream.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

using geometry::Configuration;
using geometry::Vec3;

std::vector<double> grid_values(double limit, int points) {
  CONTACTNN_REQUIRE(points >= 1, "a grid needs at least 1 point per axis, got " << points);
  CONTACTNN_REQUIRE(limit > 0.0, "grid limit must be positive, got " << limit);
  std::vector<double> values(static_cast<std::size_t>(points));
  // limit (2k + 1 - n) / n: symmetric about 0 to the last bit, and exactly 0 at the middle of an odd grid.
  for (int k = 0; k < points; ++k) {
    values[static_cast<std::size_t>(k)] =
        limit * static_cast<double>(2 * k + 1 - points) / static_cast<double>(points);
  }
  return values;
}

namespace {

/// A geometric candidate as grid indices (compact: the full list can be large).
struct Candidate {
  std::int32_t d, c, s;
};

/// The grid's nodes D, C and S (SPEC 4's frame: A at the origin, B at (1, 0, 0)). Node D lies in the xy-plane
/// with y_D > 0.
struct GridNodes {
  std::vector<Vec3> d, c, s;
};

GridNodes grid_nodes(const EnumerationOptions& options, EnumerationSummary& summary) {
  const geometry::DomainFilters& filters = options.filters;
  const auto dxy = grid_values(filters.xy_limit, options.d_xy_points);
  const auto cxy = grid_values(filters.xy_limit, options.c_xy_points);
  const auto cz = grid_values(filters.z_limit, options.c_z_points);
  const auto sxy = grid_values(filters.xy_limit, options.s_xy_points);
  const auto sz = grid_values(filters.z_limit, options.s_z_points);
  GridNodes grid;
  for (double x : dxy)
    for (double y : dxy)
      if (y > 0.0) grid.d.emplace_back(x, y, 0.0);
  for (double x : cxy)
    for (double y : cxy)
      for (double z : cz) grid.c.emplace_back(x, y, z);
  for (double x : sxy)
    for (double y : sxy)
      for (double z : sz) grid.s.emplace_back(x, y, z);
  summary.grid_points = static_cast<std::int64_t>(dxy.size() * dxy.size()) *
                        static_cast<std::int64_t>(grid.c.size()) * static_cast<std::int64_t>(grid.s.size());
  return grid;
}

/// The geometric candidates that pass the filters, in grid order. The S filters need only A, B, D, so C is
/// looped innermost.
std::vector<Candidate> geometric_candidates(const GridNodes& grid, const geometry::DomainFilters& filters) {
  std::vector<Candidate> candidates;
  const Vec3 a = Vec3::Zero();
  const Vec3 b(1.0, 0.0, 0.0);
  for (std::size_t id = 0; id < grid.d.size(); ++id) {
    const Vec3& d = grid.d[id];
    if (filters.ad_not_longer_than_ab && !(d.squaredNorm() <= 1.0)) continue;
    for (std::size_t is = 0; is < grid.s.size(); ++is) {
      const Vec3& s = grid.s[is];
      const double to_a = s.squaredNorm();
      if (filters.nearest_node_a && (to_a > (s - b).squaredNorm() || to_a > (s - d).squaredNorm())) continue;
      if (filters.segment_test_a && !geometry::passes_segment_test(a, b, d, s)) continue;
      for (std::size_t ic = 0; ic < grid.c.size(); ++ic) {
        Configuration config{{a, b, grid.c[ic], d}, s, {}};
        // The full filter (C's checks; S's again, cheaply). Normals are drawn later so as to pass.
        if (!filters.accepts(config, SurfaceKind::kBilinear)) continue;
        candidates.push_back(
            {static_cast<std::int32_t>(id), static_cast<std::int32_t>(ic), static_cast<std::int32_t>(is)});
      }
    }
  }
  return candidates;
}

/// Counts the statuses of every labelled row into `summary`, and returns the rows kept (with
/// require_projection_inside only those with status ok), in order.
LabelledSet kept_rows(const LabelledSet& all, const EnumerationOptions& options,
                      EnumerationSummary& summary) {
  const std::int64_t total = all.size();
  std::int64_t kept = 0;
  for (std::int64_t row = 0; row < total; ++row) {
    const Status status = all.status[static_cast<std::size_t>(row)];
    ++summary.status_counts[static_cast<std::size_t>(status)];
    if (!options.require_projection_inside || status == Status::kOk) ++kept;
  }
  LabelledSet result;
  result.resize(kept, options.surface);
  result.filters = options.filters;
  std::int64_t out = 0;
  for (std::int64_t row = 0; row < total; ++row) {
    const Status status = all.status[static_cast<std::size_t>(row)];
    if (options.require_projection_inside && status != Status::kOk) continue;
    result.features.row(out) = all.features.row(row);
    result.labels.row(out) = all.labels.row(row);
    result.gap[out] = all.gap[row];
    result.iterations[out] = all.iterations[row];
    result.status[static_cast<std::size_t>(out)] = status;
    result.scale[out] = all.scale[row];
    ++summary.iteration_histogram[static_cast<std::size_t>(std::min(all.iterations[row], 63))];
    ++out;
  }
  summary.kept = kept;
  return result;
}

}  // namespace

LabelledSet enumerate_configurations(const EnumerationOptions& options, EnumerationSummary& summary,
                                     const ProgressFn& progress) {
  const auto start_time = std::chrono::steady_clock::now();
  const geometry::DomainFilters& filters = options.filters;
  const SurfaceKind kind = options.surface;
  CONTACTNN_REQUIRE(options.normal_sets >= 1, "normal_sets must be >= 1, got " << options.normal_sets);

  // 1. Geometric candidates, in grid order.
  const GridNodes grid = grid_nodes(options, summary);
  const std::vector<Candidate> candidates = geometric_candidates(grid, filters);
  const std::int64_t sets = kind == SurfaceKind::kGregory ? options.normal_sets : 1;
  const std::int64_t total = static_cast<std::int64_t>(candidates.size()) * sets;
  summary.geometric_kept = total;

  // 2. Label every candidate in parallel into preallocated arrays; row order is fixed by the index.
  LabelledSet all;
  all.resize(total, kind);
  detail::ProgressCounter rows_done(progress, total, 1024);
  const Vec3 a = Vec3::Zero();
  const Vec3 b(1.0, 0.0, 0.0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t row = 0; row < total; ++row) {
    const Candidate& cand = candidates[static_cast<std::size_t>(row / sets)];
    Configuration config{
        {a, b, grid.c[static_cast<std::size_t>(cand.c)], grid.d[static_cast<std::size_t>(cand.d)]},
        grid.s[static_cast<std::size_t>(cand.s)],
        {}};
    if (kind == SurfaceKind::kGregory) {
      RandomStream random(options.seed, static_cast<std::uint64_t>(row));
      config.normals = random_node_normals(config.nodes, filters.max_normal_tilt_tangent, random);
    }
    const Label label = label_configuration(config, kind, options.projection);
    store_label(label, row, all);
    rows_done.row_done();
  }
  rows_done.finish();

  // 3. Counts, then (optionally) keep only projections inside the segment.
  LabelledSet result = kept_rows(all, options, summary);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace contactnn::dataset
