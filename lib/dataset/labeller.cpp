#include "dataset/labeller.hpp"

#include "geometry/segment_checks.hpp"
#include "geometry/surface_of.hpp"

namespace contactnn::dataset {

projection::ProjectionResult project_normalised(const geometry::Configuration& normalised, SurfaceKind kind,
                                                const projection::ProjectionOptions& options) {
  if (const auto defect = geometry::surface_defect(normalised, kind)) {
    projection::ProjectionResult result;
    result.param = projection::domain_centre(kind);
    result.status = *defect;
    return result;
  }
  return geometry::with_surface(normalised, kind, [&](const auto& surface) {
    return projection::project_point(surface, normalised.slave, options);
  });
}

Label label_configuration(const geometry::Configuration& world, SurfaceKind kind,
                          const projection::ProjectionOptions& options) {
  Label label;
  label.param = projection::domain_centre(kind);
  label.canonical_param = label.param;
  const auto normalised = geometry::normalise(world, kind);
  if (!normalised.value) {
    label.status =
        normalised.failure == geometry::NormaliseFailure::kNonFinite ? Status::kInvalid : Status::kDegenerate;
    return label;
  }
  label.features = normalised.value->features;
  label.scale = normalised.value->frame.scale();
  if (geometry::is_degenerate_segment(normalised.value->config.nodes)) {
    label.status = Status::kDegenerate;
    return label;
  }
  // Projected in the canonical frame (SPEC 4), reported in the caller's node order and orientation. For any
  // node order of one segment the canonical configuration is the same, bit for bit, and so is the label.
  const projection::ProjectionResult result = project_normalised(normalised.value->config, kind, options);
  label.param = normalised.value->to_caller(result.param, kind);
  label.canonical_param = result.param;
  label.canonical_gap = result.gap;
  label.iterations = result.iterations;
  label.status = result.status;
  label.gap = normalised.value->gap_to_caller(result.gap);
  return label;
}

void store_label(const Label& label, Eigen::Index row, LabelledSet& set) {
  for (int f = 0; f < feature_count(set.surface); ++f)
    set.features(row, f) = label.features[static_cast<std::size_t>(f)];
  set.labels(row, 0) = label.canonical_param[0];
  set.labels(row, 1) = label.canonical_param[1];
  set.gap[row] = label.canonical_gap;
  set.iterations[row] = label.iterations;
  set.status[static_cast<std::size_t>(row)] = label.status;
  set.scale[row] = label.scale;
}

}  // namespace contactnn::dataset
