#include "dataset/sampling.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "dataset/random_stream.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

using geometry::Configuration;
using geometry::Vec3;

namespace {

/// Draws that land nowhere for this long mean the filters exclude everything.
constexpr std::int64_t kMaxDrawsPerRow = 10'000'000;

/// Per-row tallies, summed after the parallel loop (integer sums: the same in any order).
struct RowTally {
  std::int64_t drawn = 0;
  std::int64_t labelled = 0;
  std::array<std::int64_t, kStatusCount> status{};
};

}  // namespace

// The proposal boxes: |AD| <= |AB| = 1 keeps D in the unit half disc; a slave nearer A than B and passing
// the segment test at A (inside the angle DAB, whose sides have y >= 0) has x_S <= 1/2 and y_S > 0.
std::optional<Configuration> draw_candidate(const EnumerationOptions& options, RandomStream& random) {
  const geometry::DomainFilters& f = options.filters;
  const double l = f.xy_limit, zl = f.z_limit;
  const double d_box = f.ad_not_longer_than_ab ? std::min(l, 1.0) : l;
  const double s_x_max = f.nearest_node_a ? std::min(l, 0.5) : l;
  const double s_y_min = f.segment_test_a ? 0.0 : -l;
  Configuration c{};
  c.nodes[0] = Vec3::Zero();
  c.nodes[1] = Vec3(1.0, 0.0, 0.0);
  c.nodes[3] = Vec3(random.uniform(-d_box, d_box), random.uniform(0.0, d_box), 0.0);
  c.slave = Vec3(random.uniform(-l, s_x_max), random.uniform(s_y_min, l), random.uniform(-zl, zl));
  c.nodes[2] = Vec3(random.uniform(-l, l), random.uniform(-l, l), random.uniform(-zl, zl));
  if (!f.accepts(c, SurfaceKind::kBilinear)) return std::nullopt;  // the geometric filters; normals later
  return c;
}

LabelledSet sample_configurations(const EnumerationOptions& options, std::int64_t count, EnumerationSummary& summary,
                                  const ProgressFn& progress) {
  const auto start_time = std::chrono::steady_clock::now();
  CONTACTNN_REQUIRE(count >= 1, "count must be >= 1, got " << count);
  const SurfaceKind kind = options.surface;
  const geometry::DomainFilters& filters = options.filters;

  LabelledSet set;
  set.resize(count, kind);
  set.filters = filters;
  std::vector<RowTally> tally(static_cast<std::size_t>(count));
  std::atomic<std::int64_t> done{0};
  std::atomic<bool> hopeless{false};
  auto last_report = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t row = 0; row < count; ++row) {
    if (hopeless.load(std::memory_order_relaxed)) continue;
    RandomStream random(options.seed, static_cast<std::uint64_t>(row));
    RowTally& t = tally[static_cast<std::size_t>(row)];
    for (;;) {
      if (t.drawn >= kMaxDrawsPerRow) {
        hopeless = true;
        break;
      }
      ++t.drawn;
      std::optional<Configuration> candidate = draw_candidate(options, random);
      if (!candidate) continue;
      Configuration& c = *candidate;
      if (kind == SurfaceKind::kGregory) {
        c.normals = random_node_normals(c.nodes, filters.max_normal_tilt_tangent, random);
      }
      const Label label = label_configuration(c, kind, options.projection);
      ++t.labelled;
      ++t.status[static_cast<std::size_t>(label.status)];
      if (options.require_projection_inside && label.status != Status::kOk) continue;
      const auto i = static_cast<Eigen::Index>(row);
      for (int f = 0; f < feature_count(kind); ++f) set.features(i, f) = label.features[static_cast<std::size_t>(f)];
      set.labels(i, 0) = label.canonical_param[0];
      set.labels(i, 1) = label.canonical_param[1];
      set.gap[i] = label.canonical_gap;
      set.iterations[i] = label.iterations;
      set.status[static_cast<std::size_t>(row)] = label.status;
      set.scale[i] = label.scale;
      break;
    }
    const std::int64_t finished = ++done;
    if (progress && omp_get_thread_num() == 0 && (finished & 255) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report > std::chrono::milliseconds(500)) {
        last_report = now;
        progress(finished, count);
      }
    }
  }
  CONTACTNN_REQUIRE(!hopeless, "no configuration of the " << to_string(kind) << " domain passed the filters in "
                                                          << kMaxDrawsPerRow << " draws: the filters exclude everything?\n"
                                                          << filters.describe());
  if (progress) progress(count, count);

  summary = EnumerationSummary{};
  for (const RowTally& t : tally) {
    summary.grid_points += t.drawn;
    summary.geometric_kept += t.labelled;
    for (int s = 0; s < kStatusCount; ++s) summary.status_counts[static_cast<std::size_t>(s)] += t.status[static_cast<std::size_t>(s)];
  }
  for (std::int64_t row = 0; row < count; ++row) {
    ++summary.iteration_histogram[static_cast<std::size_t>(std::min(set.iterations[row], 63))];
  }
  summary.kept = count;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return set;
}

}  // namespace contactnn::dataset
