#include "core/input_features.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace contactnn {

std::string_view to_string(InputFeatures features) {
  return features == InputFeatures::kPaper ? "paper" : "affine";
}

InputFeatures input_features_from_string(std::string_view name) {
  if (name == "paper") return InputFeatures::kPaper;
  if (name == "affine") return InputFeatures::kAffine;
  throw InvalidArgument("unknown input features '" + std::string(name) + "': expected 'paper' or 'affine'");
}

void map_input_features(InputFeatures features, SurfaceKind kind, const double* paper, double* inputs) {
  const int n = feature_count(kind);
  if (features == InputFeatures::kPaper) {
    std::copy(paper, paper + n, inputs);
    return;
  }
  const double xd = paper[3];
  const double yd = std::max(paper[4], 1e-300);
  const double rho = std::sqrt(xd * xd + yd * yd);
  const double height = 1.0 / std::sqrt(yd);
  // A point's affine coordinates: x = alpha + beta xd, y = beta yd.
  const double beta_c = paper[1] / yd, beta_s = paper[6] / yd;
  inputs[0] = paper[0] - xd * beta_c;
  inputs[1] = beta_c;
  inputs[2] = paper[2] * height;
  inputs[3] = rho;
  inputs[4] = xd / rho;
  inputs[5] = paper[5] - xd * beta_s;
  inputs[6] = beta_s;
  inputs[7] = paper[7] * height;
  if (kind == SurfaceKind::kGregory) {
    for (int i = 0; i < 4; ++i) {
      const double p = paper[8 + 2 * i], q = paper[9 + 2 * i];
      inputs[8 + 2 * i] = p;
      inputs[9 + 2 * i] = (p * xd + q * yd) / rho;
    }
  }
}

}  // namespace contactnn
