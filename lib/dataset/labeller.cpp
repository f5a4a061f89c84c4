#include "dataset/labeller.hpp"

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

projection::ProjectionResult project_normalised(const geometry::Configuration& normalised, SurfaceKind kind,
                                                const projection::ProjectionOptions& options) {
  switch (kind) {
    case SurfaceKind::kBilinear:
      return projection::project_point(geometry::BilinearPatch(normalised.nodes), normalised.slave, options);
    case SurfaceKind::kGregory:
      break;
  }
  throw InvalidArgument("the Gregory surface is not implemented yet in this build");
}

Label label_configuration(const geometry::Configuration& world, SurfaceKind kind,
                          const projection::ProjectionOptions& options) {
  Label label;
  label.param = projection::domain_centre(kind);
  const auto normalised = geometry::normalise(world, kind);
  if (!normalised.value) {
    label.status = normalised.failure == geometry::NormaliseFailure::kNonFinite ? Status::kInvalid
                                                                                 : Status::kDegenerate;
    return label;
  }
  label.features = normalised.value->features;
  label.scale = normalised.value->frame.scale();
  if (geometry::is_degenerate_segment(normalised.value->config.nodes)) {
    label.status = Status::kDegenerate;
    return label;
  }
  const projection::ProjectionResult result = project_normalised(normalised.value->config, kind, options);
  label.param = result.param;
  label.iterations = result.iterations;
  label.status = result.status;
  label.gap = result.gap / label.scale;
  return label;
}

}  // namespace contactnn::dataset
