// A trained network as a self-contained C99 header, for pasting into a finite-element code: lib/search's own
// C99 kernels (canonical_frame.h, vector_sigmoid.h) embedded verbatim, the network's parameters, scaling and
// training domain as tables, and a generated forward pass over blocks of queries.
#pragma once

#include <string>

#include "search/network_model.hpp"

namespace contactnn::search {

struct CHeaderOptions {
  std::string prefix = "contactnn_net";  ///< C identifier prefix of everything the header defines
  bool check_domain = true;              ///< test the network's training domain (return code 2 outside it)
  std::string description;               ///< free text for the header comment (provenance)
};

/// C99 source (needs <math.h>, <stddef.h>, <stdint.h>, <string.h>, which it includes) defining, with
/// `static inline` functions and `static const` tables only:
///
///   int PREFIX_local_coordinates(const double raw[N], double out[2]);
///   void PREFIX_local_coordinates_batch(size_t n, const double* raw, double* out, int* status);
///
/// raw = ax ay az bx by bz cx cy cz dx dy dz sx sy sz (N = 15, SPEC 6 order), for Gregory followed by
/// nax nay naz ... ndz (N = 27), in any node order; the batch reads n such rows (n x N, row-major) and writes
/// n rows of out (n x 2) and n status codes. Each query is LocalSearch's "network" method (the model's own
/// canonical frame, tie averaging over every canonical form, input map, scaling, forward pass in the
/// network's precision, domain test), computed by the same C99 kernels: out = (xi, eta) or (u, v) in the
/// caller's node order. Returns (status) 0 on success, 1 (out untouched) for a non-finite input or a
/// degenerate segment, 2 (out written) when the canonical configuration lies outside the training domain
/// (TrainingDomain::contains: feature ranges and the generator's filters; never with check_domain false).
/// The batch gives the same bits as the one-query function when the header is compiled without floating-point
/// contraction (ISO C, e.g. -std=c99, or -ffp-contract=off); with contraction (GNU C, C++) the two contract
/// differently and agree to the rounding of the network's precision (~1e-7 relative for a float network).
/// Two headers with different prefixes can be included in one translation unit (the embedded kernels have
/// fixed include guards and version macros, checked by #error).
/// Throws InvalidArgument when the prefix is not a C identifier or a parameter is not finite.
[[nodiscard]] std::string export_c_header(const NetworkModel& model, const CHeaderOptions& options);

}  // namespace contactnn::search
