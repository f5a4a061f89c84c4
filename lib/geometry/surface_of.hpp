// The surface of a configuration, whichever its kind: the one place that turns a SurfaceKind into a
// BilinearPatch or a GregoryPatch, so a new surface slots in here.
#pragma once

#include <optional>

#include "core/conventions.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/configuration.hpp"
#include "geometry/gregory_patch.hpp"

namespace contactnn::geometry {

/// Why `config` has no surface of `kind`: invalid for a non-finite Gregory input, degenerate for a Gregory
/// segment GregoryPatch::diagnose rejects (zero normal, normal along an edge, collapsed edge); std::nullopt
/// when the surface exists. A bilinear facet always exists (its degeneracy is judged by the projection).
[[nodiscard]] inline std::optional<Status> surface_defect(const Configuration& config, SurfaceKind kind) {
  if (kind != SurfaceKind::kGregory) return std::nullopt;
  const GregoryDefect defect = GregoryPatch::diagnose(config.nodes, config.normals);
  if (defect == GregoryDefect::kNone) return std::nullopt;
  return defect == GregoryDefect::kNonFinite ? Status::kInvalid : Status::kDegenerate;
}

/// Returns fn(surface) for the BilinearPatch or GregoryPatch of `config`; `fn` takes either (a generic
/// lambda). Precondition: !surface_defect(config, kind).
template <class Fn>
decltype(auto) with_surface(const Configuration& config, SurfaceKind kind, Fn&& fn) {
  if (kind == SurfaceKind::kGregory) return fn(GregoryPatch(config.nodes, config.normals));
  return fn(BilinearPatch(config.nodes));
}

}  // namespace contactnn::geometry
