// The methods the study compares, each from raw world coordinates (paper Sections 5.3.2 and 6.3.3): the
// network (the Section 4 normalisation, then a forward pass), plain Newton with a fixed iteration count
// from the segment centre, plain Newton to convergence, and the reference (label) solver.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "geometry/domain.hpp"
#include "geometry/affine_frame.hpp"
#include "geometry/configuration.hpp"
#include "projection/newton_projection.hpp"

namespace contactnn::eval {

/// A network as the study uses it: `predict(features, out)` maps the normalised features (SPEC 4,
/// feature_count values) to the two local coordinates. Copyable: each thread works on its own copy
/// (the forward pass buffers), so predict may mutate the object.
template <class P>
concept FeaturePredictor = std::copy_constructible<P> && requires(P& p, const double* features, double* out) {
  p.predict(features, out);
};

/// One method of the study.
struct Method {
  enum class Kind { kNetwork, kNewtonFixed, kNewtonConverged, kReference };
  Kind kind = Kind::kNetwork;
  int iterations = 0;  ///< kNewtonFixed only: the fixed iteration count

  /// "network", "newton_5", "newton_converged", "reference": the names in errors.csv and speed.csv.
  [[nodiscard]] std::string name() const;
  /// One line for the report, e.g. "plain Newton, 5 iterations from the segment centre".
  [[nodiscard]] std::string description() const;
};

/// The methods of errors.csv: the network, Newton with k = 1..max_fixed_iterations, Newton to convergence.
[[nodiscard]] std::vector<Method> error_table_methods(int max_fixed_iterations);

/// Settings of the Newton methods; defaults are an FE code's plain Newton.
struct NewtonMethodOptions {
  int converged_max_iterations = 50;  ///< newton_until_converged's limit
  double converged_tol_param = 1e-10; ///< its step tolerance (parameter units)
  projection::ProjectionOptions reference;  ///< the label solver's settings (gen-configs' defaults)
};

/// An estimate of the local coordinates by one method for one configuration.
struct Estimate {
  std::array<double, 2> param{0.0, 0.0};
  /// Network: ok, out_of_domain (the normalised input is outside the TrainingDomain; param still the
  /// prediction), invalid (non-finite input) or degenerate (no canonical normalised frame). Newton with fixed
  /// iterations: ok (the last iterate, wherever it is), or degenerate / invalid when no Gregory patch exists.
  /// Newton to convergence and the reference: the solver's status (ok, outside, no_convergence, degenerate,
  /// invalid).
  Status status = Status::kOk;
  int iterations = 0;  ///< Newton iterations used (the fixed count for newton_k); 0 for the network
};

/// The network on a world configuration: bring it to the canonical normalised frame (SPEC 4), predict, map
/// the prediction back to the caller's node order, then check `domain` (skipped when null). On a tie
/// (geometry::canonical_forms: a slave midway between two nodes, ...) the prediction is the mean over the
/// tied canonical forms and the domain must hold every one, so the answer does not depend on the node order.
/// Allocation-free when the predictor is.
template <FeaturePredictor P>
[[nodiscard]] Estimate network_estimate(const geometry::Configuration& world, SurfaceKind kind, P& predictor,
                                        const geometry::TrainingDomain* domain) {
  Estimate e;
  e.param = projection::domain_centre(kind);
  const geometry::CanonicalForms forms = geometry::canonical_forms(world, kind);
  // Without a frame at the canonical corner (a straight angle there) the network's inputs do not exist.
  if (forms.count == 0 || !forms.form[0].canonical) {
    e.status = forms.count == 0 && forms.failure == geometry::NormaliseFailure::kNonFinite ? Status::kInvalid
                                                                                          : Status::kDegenerate;
    return e;
  }
  std::array<double, 2> sum{0.0, 0.0};
  bool inside = true;
  for (int k = 0; k < forms.count; ++k) {
    const geometry::NormalisedConfiguration& n = forms.form[static_cast<std::size_t>(k)];
    std::array<double, 2> p{};
    predictor.predict(n.features.data(), p.data());
    p = n.to_caller(p, kind);
    sum[0] += p[0];
    sum[1] += p[1];
    inside = inside && (domain == nullptr || domain->contains(n.config, n.features.data()));
  }
  e.param = {sum[0] / forms.count, sum[1] / forms.count};
  if (!inside) e.status = Status::kOutOfDomain;
  return e;
}

/// Plain Newton (projection::newton_fixed_iterations) on the patch built from the world nodes (and, for
/// Gregory, node normals), `iterations` undamped steps from the domain centre. Status ok with the last
/// iterate, wherever it is; degenerate or invalid when no Gregory patch exists (GregoryPatch::diagnose).
/// Building the patch is Newton's only preprocessing and is part of the method.
[[nodiscard]] Estimate newton_fixed_estimate(const geometry::Configuration& world, SurfaceKind kind, int iterations);

/// Plain Newton to convergence (projection::newton_until_converged) from the domain centre, world coordinates.
[[nodiscard]] Estimate newton_converged_estimate(const geometry::Configuration& world, SurfaceKind kind,
                                                 const NewtonMethodOptions& options);

/// The reference solver (projection::project_point) on the world coordinates.
[[nodiscard]] Estimate reference_estimate(const geometry::Configuration& world, SurfaceKind kind,
                                          const NewtonMethodOptions& options);

/// True when `param` is usable as an estimate: finite and inside the parameter domain enlarged by
/// `box_margin` domain widths on each side (0.5: [-2, 2]^2 for bilinear, [-0.5, 1.5]^2 for Gregory).
/// An estimate beyond it is a failure of the method, counted and never averaged in.
[[nodiscard]] bool inside_box(const std::array<double, 2>& param, SurfaceKind kind, double box_margin);

/// True when `param` lies in the parameter domain enlarged by `margin` (parameter units).
[[nodiscard]] bool inside_domain(const std::array<double, 2>& param, SurfaceKind kind, double margin);

}  // namespace contactnn::eval
