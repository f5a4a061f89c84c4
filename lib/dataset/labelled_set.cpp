#include "dataset/labelled_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace contactnn::dataset {

void LabelledSet::resize(Eigen::Index n, SurfaceKind kind) {
  surface = kind;
  features.resize(n, feature_count(kind));
  labels.resize(n, 2);
  gap.resize(n);
  iterations.resize(n);
  status.resize(static_cast<std::size_t>(n));
  scale.resize(n);
}

void LabelledSet::validate(const std::string& source) const {
  const Eigen::Index n = features.rows();
  CONTACTNN_REQUIRE_AS(FormatError, features.cols() == feature_count(surface),
                       source << ": features have " << features.cols() << " columns, expected "
                              << feature_count(surface) << " for a " << to_string(surface) << " dataset");
  CONTACTNN_REQUIRE_AS(
      FormatError, labels.rows() == n && labels.cols() == 2,
      source << ": labels are " << labels.rows() << "x" << labels.cols() << ", expected " << n << "x2");
  CONTACTNN_REQUIRE_AS(FormatError,
                       gap.size() == n && iterations.size() == n && scale.size() == n &&
                           static_cast<Eigen::Index>(status.size()) == n,
                       source << ": gap/iterations/status/scale have " << gap.size() << "/"
                              << iterations.size() << "/" << status.size() << "/" << scale.size()
                              << " rows, expected " << n);
  // An ok row is a label inside the domain (SPEC 2; the labeller's margin is 1e-10, this test's 1e-6) with
  // features a float network can take (beyond the float range they became inf in training, an internal
  // error).
  const double lo = surface == SurfaceKind::kGregory ? 0.0 : -1.0, margin = 1e-6;
  const double largest = std::numeric_limits<float>::max();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (status[static_cast<std::size_t>(i)] != Status::kOk) continue;
    CONTACTNN_REQUIRE_AS(FormatError,
                         features.row(i).allFinite() && labels.row(i).allFinite() && std::isfinite(gap[i]),
                         source << ": row " << i << " has status ok but a non-finite value");
    double biggest = 0.0;  // a plain loop: Eigen's vectorised maxCoeff draws a false GCC 12 warning here
    for (Eigen::Index c = 0; c < features.cols(); ++c) biggest = std::max(biggest, std::abs(features(i, c)));
    CONTACTNN_REQUIRE_AS(
        FormatError, biggest <= largest,
        source << ": row " << i << " has a feature beyond the float range (" << biggest << ")");
    for (int c = 0; c < 2; ++c) {
      const double x = labels(i, c);
      CONTACTNN_REQUIRE_AS(FormatError, x >= lo - margin && x <= 1.0 + margin,
                           source << ": row " << i << " has status ok but label " << c << " = " << x
                                  << ", outside the " << to_string(surface) << " domain [" << lo << ", 1]");
    }
  }
}

}  // namespace contactnn::dataset
