// Labels one world configuration: bring it to the canonical normalised frame (SPEC 4), build the surface
// (geometry/surface_of.hpp), project (SPEC 2), and map the result back to the caller's node order.
#pragma once

#include <array>

#include "core/conventions.hpp"
#include "dataset/labelled_set.hpp"
#include "geometry/affine_frame.hpp"
#include "projection/newton_projection.hpp"

namespace contactnn::dataset {

/// The label of one configuration. Coordinates and gap are finite whenever status is ok or outside.
struct Label {
  std::array<double, 2> param{0.0, 0.0};  ///< (xi, eta) bilinear, (u, v) Gregory, in the caller's node order
  double gap = 0.0;                       ///< in world units, along the caller's own P_xi x P_eta
  int iterations = 0;
  Status status = Status::kInvalid;
  double scale = 0.0;  ///< raw-to-normalised scale 1/|AB| (0 if no frame)
  /// The same projection in the canonical configuration (SPEC 4) the features describe: what a dataset row
  /// holds beside its features, and what a network is trained to predict.
  std::array<double, 2> canonical_param{0.0, 0.0};
  double canonical_gap = 0.0;         ///< in normalised units, along the canonical P_s x P_t
  std::array<double, 16> features{};  ///< canonical normalised inputs (first feature_count(kind) used)
};

/// Labels `world`: invalid for a non-finite input, degenerate when the frame does not exist or the segment
/// is collapsed (is_degenerate_segment) or a Gregory node normal is unusable; otherwise project_point's
/// status in the normalised frame, where the projection is computed (scale-free tolerances).
[[nodiscard]] Label label_configuration(const geometry::Configuration& world, SurfaceKind kind,
                                        const projection::ProjectionOptions& options = {});

/// Writes row `row` of `set` (allocated for it) from `label`: its features, canonical local coordinates,
/// canonical gap, iterations, status and scale (the generators' one way of filling a dataset row).
void store_label(const Label& label, Eigen::Index row, LabelledSet& set);

/// Projects a configuration already in the normalised frame (gap in frame units, scale 1).
[[nodiscard]] projection::ProjectionResult project_normalised(
    const geometry::Configuration& normalised, SurfaceKind kind,
    const projection::ProjectionOptions& options = {});

}  // namespace contactnn::dataset
