#include "eval/methods.hpp"

#include <cmath>

#include "core/error.hpp"
#include "geometry/surface_of.hpp"

namespace contactnn::eval {

namespace {

/// Builds the surface from the world configuration and applies `solve` to it. A Gregory segment without a
/// patch gives status invalid or degenerate, as the labeller reports it.
template <class Solve>
Estimate on_patch(const geometry::Configuration& world, SurfaceKind kind, Solve&& solve) {
  if (const auto defect = geometry::surface_defect(world, kind)) {
    Estimate e;
    e.param = projection::domain_centre(kind);
    e.status = *defect;
    return e;
  }
  return geometry::with_surface(world, kind, solve);
}

}  // namespace

std::string Method::name() const {
  switch (kind) {
    case Kind::kNetwork: return "network";
    case Kind::kNewtonFixed: return "newton_" + std::to_string(iterations);
    case Kind::kNewtonConverged: return "newton_converged";
    case Kind::kReference: return "reference";
  }
  return "unknown";
}

std::string Method::description() const {
  switch (kind) {
    case Kind::kNetwork: return "network: Section 4 normalisation of the world coordinates, then the forward pass";
    case Kind::kNewtonFixed:
      return "plain Newton, " + std::to_string(iterations) + (iterations == 1 ? " iteration" : " iterations") +
             " from the segment centre (no line search, no convergence test)";
    case Kind::kNewtonConverged: return "plain Newton from the segment centre until the step is below the tolerance";
    case Kind::kReference: return "reference solver (the labels): damped Newton from a grid of starts";
  }
  return "unknown";
}

std::vector<Method> error_table_methods(int max_fixed_iterations) {
  CONTACTNN_REQUIRE(max_fixed_iterations >= 1, "max_fixed_iterations = " << max_fixed_iterations << ", expected >= 1");
  std::vector<Method> methods{{Method::Kind::kNetwork, 0}};
  for (int k = 1; k <= max_fixed_iterations; ++k) methods.push_back({Method::Kind::kNewtonFixed, k});
  methods.push_back({Method::Kind::kNewtonConverged, 0});
  return methods;
}

Estimate newton_fixed_estimate(const geometry::Configuration& world, SurfaceKind kind, int iterations) {
  return on_patch(world, kind, [&](const auto& patch) {
    Estimate e;
    e.param = projection::newton_fixed_iterations(patch, world.slave, iterations, projection::domain_centre(kind));
    e.iterations = iterations;
    return e;
  });
}

Estimate newton_converged_estimate(const geometry::Configuration& world, SurfaceKind kind,
                                   const NewtonMethodOptions& options) {
  return on_patch(world, kind, [&](const auto& patch) {
    const projection::ProjectionResult r =
        projection::newton_until_converged(patch, world.slave, projection::domain_centre(kind),
                                           options.converged_max_iterations, options.converged_tol_param);
    return Estimate{r.param, r.status, r.iterations};
  });
}

Estimate reference_estimate(const geometry::Configuration& world, SurfaceKind kind, const NewtonMethodOptions& options) {
  return on_patch(world, kind, [&](const auto& patch) {
    const projection::ProjectionResult r = projection::project_point(patch, world.slave, options.reference);
    return Estimate{r.param, r.status, r.iterations};
  });
}

bool inside_domain(const std::array<double, 2>& param, SurfaceKind kind, double margin) {
  const ParamDomain d = param_domain(kind);
  return param[0] >= d.lo - margin && param[0] <= d.hi + margin && param[1] >= d.lo - margin &&
         param[1] <= d.hi + margin;
}

bool inside_box(const std::array<double, 2>& param, SurfaceKind kind, double box_margin) {
  const ParamDomain d = param_domain(kind);
  // inside_domain is false for NaN, so non-finite estimates are outside every box.
  return inside_domain(param, kind, box_margin * (d.hi - d.lo));
}

}  // namespace contactnn::eval
