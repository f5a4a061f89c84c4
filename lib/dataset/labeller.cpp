#include "dataset/labeller.hpp"

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

projection::ProjectionResult project_normalised(const geometry::Configuration& normalised, SurfaceKind kind,
                                                const projection::ProjectionOptions& options) {
  switch (kind) {
    case SurfaceKind::kBilinear:
      return projection::project_point(geometry::BilinearPatch(normalised.nodes), normalised.slave, options);
    case SurfaceKind::kGregory: {
      const auto defect = geometry::GregoryPatch::diagnose(normalised.nodes, normalised.normals);
      if (defect != geometry::GregoryDefect::kNone) {
        projection::ProjectionResult result;
        result.param = projection::domain_centre(kind);
        result.status = defect == geometry::GregoryDefect::kNonFinite ? Status::kInvalid : Status::kDegenerate;
        return result;
      }
      return projection::project_point(geometry::GregoryPatch(normalised.nodes, normalised.normals),
                                       normalised.slave, options);
    }
  }
  throw InvalidArgument("unknown surface kind " + std::to_string(static_cast<int>(kind)));
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
