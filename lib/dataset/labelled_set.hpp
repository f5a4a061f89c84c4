// A labelled set of configurations in the normalised frame: what gen-configs writes and train-net and
// evaluate-net read.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "geometry/domain.hpp"

namespace contactnn::dataset {

template <class T>
using MatrixRM = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Row i of every member belongs to configuration i.
struct LabelledSet {
  SurfaceKind surface = SurfaceKind::kBilinear;
  MatrixRM<double> features;  ///< N x feature_count(surface): normalised inputs (SPEC 4, kFeatureNames order)
  MatrixRM<double> labels;    ///< N x 2: (xi, eta) for bilinear, (u, v) for Gregory; Newton reference, in
                              ///< the canonical configuration the features describe (SPEC 4)
  Eigen::VectorXd gap;  ///< N: signed gap n.(S - P) in normalised units (negative: penetration), canonical
  Eigen::VectorXi iterations;       ///< N: Newton iterations of the reported solution's start
  std::vector<Status> status;       ///< N: projection status (SPEC 2)
  Eigen::VectorXd scale;            ///< N: raw-to-normalised scale 1/|AB| (1 for enumerated configurations)
  std::string config_toml;          ///< effective generator config
  geometry::DomainFilters filters;  ///< the geometric filters the configurations satisfy

  [[nodiscard]] Eigen::Index size() const { return features.rows(); }
  /// Allocates every member for n rows of `surface` (values unset).
  void resize(Eigen::Index n, SurfaceKind kind);
  /// Throws FormatError (naming `source`) unless every member has the same row count, the feature count
  /// matches the surface, and every value with status ok is finite.
  void validate(const std::string& source) const;
};

}  // namespace contactnn::dataset
