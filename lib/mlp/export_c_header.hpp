// A trained network as a self-contained C99 header, for pasting into a finite-element code.
#pragma once

#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "mlp/network.hpp"

namespace contactnn::mlp {

struct CHeaderOptions {
  std::string prefix = "contactnn_net";  ///< C identifier prefix of everything the header defines
  SurfaceKind surface = SurfaceKind::kBilinear;
  std::vector<double> domain_min, domain_max;  ///< per-feature training domain; empty: no domain check
  std::string description;                     ///< free text for the header comment (provenance)
};

/// C99 source defining, with `static inline` functions and `static const` tables only (needs <math.h>):
///
///   int PREFIX_local_coordinates(const double raw[N], double out[2]);
///
/// raw = ax ay az bx by bz cx cy cz dx dy dz sx sy sz (N = 15, SPEC 6 order), for Gregory followed by
/// nax nay naz ... ndz (N = 27), in any node order. It applies the canonical Section 4 normalisation
/// exactly as geometry::normalise does (SPEC 4: relabelling, frame, z orientation), the network's input
/// scaling, the forward pass in the network's precision, the output scaling and the map back to the
/// caller's node order; out = (xi, eta) or (u, v). Returns 0 on success, 1 (out untouched) for a
/// non-finite input or a degenerate segment, 2 (out written) when a feature lies outside
/// [domain_min, domain_max] (relative slack 1e-9; the generator's filters are not checked).
/// Throws InvalidArgument when the network's input count is not feature_count(surface), it does not have
/// 2 outputs, or the prefix is not a C identifier.
template <class Real>
[[nodiscard]] std::string export_c_header(const Network<Real>& network, const CHeaderOptions& options);

}  // namespace contactnn::mlp
