// A network for FaceSearch on the quadratic faces (tri6, quad8), in the paper's manner (Section 4, SPEC 4)
// extended to the face's nodes: the face brought to its canonical node order (the corner nearest S first,
// then the mirror when the edge to the last corner is longer than the edge to the second: 6 symmetries of a
// triangle, 8 of a quad) and its normalised frame (A at the origin, B on +x at distance 1, the third corner
// of a triangle or D of a quad in the xy-plane with y > 0). What the network sees (its features):
//   tri6   x_C, y_C; each mid-side node's offset from its chord's midpoint (x, y, z; edges A-B, B-C, C-A);
//   the
//          corner triangle's (r0, s0) of S; z_S                                                   (14 inputs)
//   quad8  x_C, y_C, z_C, x_D, y_D; the mid-side offsets (edges A-B, B-C, C-D, D-A); the corners' bilinear
//          closed form (xi0, eta0) of S (LocalSearch's closed form); z_S                          (20 inputs)
// and what it gives: the correction to that closed form, (r - r0, s - s0) or (xi - xi0, eta - eta0), in the
// canonical parametrisation; the estimate, the closed form plus the correction, is mapped back to the
// caller's node order by the inverse symmetry. The closed form is exact on a face whose mid-side nodes sit at
// their chords' midpoints (and, for the quad, whose corners are flat): the network learns only what the
// curvature adds, a small quantity (on tet-press's tri6 faces the closed form is off by 0.02 of the domain,
// the full coordinates by up to 1), so the same output accuracy is a far smaller error (docs/library.md
// "Faces"). Ties (two corners equally near S) take the first in the caller's order. The training domain is a
// box of the features (each between the training set's extremes).
#pragma once

#include <vector>

#include "mlp/network.hpp"
#include "search/face_search.hpp"
#include "search/network_model.hpp"

namespace contactnn::search {

/// Inputs of a face network: 14 (tri6), 20 (quad8); 0 for tri3 (no network: its closed form is exact).
[[nodiscard]] constexpr int face_feature_count(FaceKind kind) {
  return kind == FaceKind::kTri6 ? 14 : (kind == FaceKind::kQuad8 ? 20 : 0);
}

/// The canonical form of one query (`raw`: face_raw_columns(kind) values): its features (face_feature_count
/// values), the caller's corner at each canonical slot (`order`: 3 or 4 values) and `base` (2 values: the
/// corner facet's closed form in the canonical parametrisation, which the network's output corrects). False
/// (nothing set) where the face has no frame: a non-finite value, coincident canonical corners A and B, the
/// third corner (triangle) or D (quad) on the line AB, or a quad whose corner facet has no closed form.
bool face_canonical_form(FaceKind kind, const double* raw, double* features, int* order, double* base);
/// The canonical local coordinates of the caller's (s, t) for a face in `order`, and back.
void face_param_to_canonical(FaceKind kind, const int* order, double& s, double& t);
void face_param_to_caller(FaceKind kind, const int* order, double& s, double& t);

class FaceNetwork {
 public:
  /// `feature_min`, `feature_max`: the training domain (face_feature_count values each, min <= max). Throws
  /// InvalidArgument for tri3, a network whose input count is not face_feature_count(kind) or without 2
  /// outputs, or bounds of the wrong size or order. Real: float or double (the network's own precision;
  /// instantiated for both).
  template <class Real>
  FaceNetwork(FaceKind kind, const mlp::Network<Real>& network, std::vector<double> feature_min,
              std::vector<double> feature_max);

  [[nodiscard]] FaceKind face() const { return kind_; }
  [[nodiscard]] const NetworkModel& model() const { return model_; }
  [[nodiscard]] const std::vector<double>& feature_min() const { return min_; }
  [[nodiscard]] const std::vector<double>& feature_max() const { return max_; }
  /// The bounds as the kernels test them: the extremes widened by 1e-9 of each range (at least 1e-9).
  [[nodiscard]] const double* lo() const { return lo_.data(); }
  [[nodiscard]] const double* hi() const { return hi_.data(); }

 private:
  void check_bounds();
  FaceKind kind_;
  NetworkModel model_;
  std::vector<double> min_, max_, lo_, hi_;
};

}  // namespace contactnn::search
