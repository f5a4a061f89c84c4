// A network for FaceSearch on the quadratic faces (tri6, quad8), in the paper's manner (Section 4, SPEC 4)
// extended to the face's nodes: the face brought to its canonical node order (the corner nearest S first, then
// the mirror when the edge to the last corner is longer than the edge to the second: 6 symmetries of a
// triangle, 8 of a quad), the normalised frame of its corners (A at the origin, B on +x at distance 1, the
// third corner of a triangle or D of a quad in the xy-plane with y > 0), and the node coordinates in that frame
// as inputs:
//   tri6   x_C, y_C, then x, y, z of the mid-side nodes of A-B, B-C, C-A, then x_S, y_S, z_S      (14 inputs)
//   quad8  x_C, y_C, z_C, x_D, y_D, then x, y, z of the mid-side nodes of A-B, B-C, C-D, D-A, then S (20 inputs)
// and the local coordinates of the closest point in the canonical parametrisation as outputs, mapped back to
// the caller's node order by the inverse symmetry. Ties (two corners equally near S) take the first in the
// caller's order. The training domain is a box of the features (each between the training set's extremes).
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
/// values) and the caller's corner at each canonical corner slot (`order`: 3 or 4 values). False (features not
/// set) where the face has no frame: a non-finite value, coincident canonical corners A and B, or the third
/// corner (triangle) or D (quad) on the line AB.
bool face_canonical_form(FaceKind kind, const double* raw, double* features, int* order);
/// The canonical local coordinates of the caller's (s, t) for a face in `order`, and back.
void face_param_to_canonical(FaceKind kind, const int* order, double& s, double& t);
void face_param_to_caller(FaceKind kind, const int* order, double& s, double& t);

class FaceNetwork {
 public:
  /// `feature_min`, `feature_max`: the training domain (face_feature_count values each, min <= max). Throws
  /// InvalidArgument for tri3, a network whose input count is not face_feature_count(kind) or without 2 outputs,
  /// or bounds of the wrong size or order.
  FaceNetwork(FaceKind kind, const mlp::Network<float>& network, std::vector<double> feature_min,
              std::vector<double> feature_max);
  FaceNetwork(FaceKind kind, const mlp::Network<double>& network, std::vector<double> feature_min,
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
