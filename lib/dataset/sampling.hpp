// Random configurations of the paper's domains (Sections 5.1 and 6.3.1): the same filters as the grid
// enumeration, drawn uniformly instead of on a grid, labelled by Newton projection. A held-out sample is
// one drawn with another seed.
#pragma once

#include <cstdint>
#include <optional>

#include "dataset/enumeration.hpp"
#include "dataset/labelled_set.hpp"
#include "dataset/random_stream.hpp"

namespace contactnn::dataset {

/// `count` configurations drawn uniformly from the domain of `options` (surface, filters, normal tilts,
/// require_projection_inside; the grid sizes are not used): x, y of C, D and S uniform in (-xy_limit,
/// xy_limit) with y_D > 0, z of C and S uniform in (-z_limit, z_limit), every filter applied by rejection of
/// the whole configuration (so the density is uniform on the accepted set, not biased towards hard-to-hit
/// corners), Gregory node normals as in the enumeration. Row i is drawn from the random stream
/// (options.seed, i) until accepted: the set is identical for any thread count. `summary.grid_points`
/// counts the candidates drawn, `geometric_kept` those that passed the filters and were labelled.
/// Throws InvalidArgument for count < 1 or a domain no draw lands in (the first 10^7 draws of row 0 fail).
/// One candidate drawn from `random` in the normalised frame (A at the origin, B = (1, 0, 0)), returned
/// when it passes the geometric filters of `options` (without node normals and labels). The proposal boxes
/// are the filter boxes, shrunk only where a filter excludes the rest exactly, so accepted candidates are
/// uniform on the accepted set.
[[nodiscard]] std::optional<geometry::Configuration> draw_candidate(const EnumerationOptions& options,
                                                                    RandomStream& random);

[[nodiscard]] LabelledSet sample_configurations(const EnumerationOptions& options, std::int64_t count,
                                                EnumerationSummary& summary, const ProgressFn& progress = {});

}  // namespace contactnn::dataset
