#include "dataset/labelled_set.hpp"

#include <cmath>

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
  CONTACTNN_REQUIRE_AS(FormatError, labels.rows() == n && labels.cols() == 2,
                       source << ": labels are " << labels.rows() << "x" << labels.cols() << ", expected " << n << "x2");
  CONTACTNN_REQUIRE_AS(FormatError,
                       gap.size() == n && iterations.size() == n && scale.size() == n &&
                           static_cast<Eigen::Index>(status.size()) == n,
                       source << ": gap/iterations/status/scale have " << gap.size() << "/" << iterations.size() << "/"
                              << status.size() << "/" << scale.size() << " rows, expected " << n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (status[static_cast<std::size_t>(i)] != Status::kOk) continue;
    CONTACTNN_REQUIRE_AS(FormatError,
                         features.row(i).allFinite() && labels.row(i).allFinite() && std::isfinite(gap[i]),
                         source << ": row " << i << " has status ok but a non-finite value");
  }
}

}  // namespace contactnn::dataset
