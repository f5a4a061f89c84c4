#include "dataset/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "dataset/random_stream.hpp"
#include "dataset/row_sampler.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

using geometry::Configuration;
using geometry::Vec3;

namespace {

/// Draws that land nowhere for this long mean the filters exclude everything.
constexpr std::int64_t kMaxDrawsPerRow = 10'000'000;

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

LabelledSet sample_configurations(const EnumerationOptions& options, std::int64_t count,
                                  EnumerationSummary& summary, const ProgressFn& progress) {
  const SurfaceKind kind = options.surface;
  const geometry::DomainFilters& filters = options.filters;
  std::ostringstream hopeless;
  hopeless << "no configuration of the " << to_string(kind) << " domain passed the filters in "
           << kMaxDrawsPerRow << " draws: the filters exclude everything?\n"
           << filters.describe();
  LabelledSet set = detail::sample_rows(
      kind, count, options.seed, kMaxDrawsPerRow,
      [&](RandomStream& random) {
        detail::Attempt a;
        std::optional<Configuration> c = draw_candidate(options, random);
        if (!c) return a;
        if (kind == SurfaceKind::kGregory) {
          c->normals = random_node_normals(c->nodes, filters.max_normal_tilt_tangent, random);
        }
        a.label = label_configuration(*c, kind, options.projection);
        a.keep = !options.require_projection_inside || a.label->status == Status::kOk;
        return a;
      },
      summary, progress, hopeless.str());
  set.filters = filters;
  return set;
}

}  // namespace contactnn::dataset
