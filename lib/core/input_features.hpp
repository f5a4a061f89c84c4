// What a network sees of a configuration: the paper's normalised coordinates (SPEC 4), or the same
// configuration in the affine frame of its edges AB and AD, which keeps thin segments well conditioned.
#pragma once

#include <cstdint>
#include <string_view>

#include "core/conventions.hpp"

namespace contactnn {

/// The input map of a network (part of its scaling, recorded in its file).
///  - kPaper: the features of SPEC 4 as they are: xc yc zc xd yd xs ys zs (+ pa qa ... qd for Gregory).
///  - kAffine: with A = 0, B = (1, 0, 0), D = (xd, yd, 0) of the canonical frame, a point (x, y, z) in the
///    affine frame of AB and AD: beta = y / yd, alpha = x - xd beta, gamma = z / sqrt(yd) (heights over the
///    square root of the area |AB x AD|, a length between the two edges). Inputs:
///      alpha_C beta_C gamma_C rho kappa alpha_S beta_S gamma_S
///    with rho = |AD| / |AB| and kappa = cos(angle DAB) (the metric, as separate inputs). For Gregory the
///    node normals follow as their slopes along AB and along AD: p and (p xd + q yd) / rho for each node. On
///    a parallelogram xi = 2 alpha_S - 1 and eta = 2 beta_S - 1 exactly, whatever its aspect ratio: in the
///    paper's frame a segment of aspect 30 has yd = 0.03 and the slave's whole eta range lies in a strip of
///    that width.
enum class InputFeatures : std::uint8_t { kPaper = 0, kAffine = 1 };

/// "paper" or "affine".
[[nodiscard]] std::string_view to_string(InputFeatures features);
/// Inverse of to_string; InvalidArgument naming the accepted values otherwise.
[[nodiscard]] InputFeatures input_features_from_string(std::string_view name);

/// The network inputs of `kind` (feature_count(kind) values) from the paper's features: a copy for kPaper,
/// the affine inputs above for kAffine. `paper` and `inputs` must not overlap. A canonical configuration has
/// yd > 0; a yd below 1e-300 is taken as 1e-300 (the inputs stay finite).
void map_input_features(InputFeatures features, SurfaceKind kind, const double* paper, double* inputs);

}  // namespace contactnn
