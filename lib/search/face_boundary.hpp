// The closest point of a whole face for lib/search's methods (SearchOptions::closest_point_on_face): a
// method's answer outside its segment goes to the nearest point of the segment's boundary, as the surface
// search's reference does (projection/closest_point_on_face.hpp).
#pragma once

#include <cstddef>

#include "core/conventions.hpp"

namespace contactnn::search::detail {

/// For one query (raw: its 15 or 27 values, SPEC 6) whose method answered `outside`: the nearest point of the
/// segment's four edges (straight on the bilinear facet, exact; the cubic boundary curves of the Gregory
/// patch, a 1-D projection), its ends included. Writes param (2 values, the caller's node order), gap (if not
/// null:
/// +-|S - P|, the sign of (S - P).n with n the unit normal P_s x P_t at P), status ok and location (edge or
/// vertex; if not null). A Gregory segment without a patch is left as it is.
template <class Real>
void move_to_face_boundary(SurfaceKind kind, const Real* raw, Real* param, Real* gap, Status* status,
                           Location* location);

}  // namespace contactnn::search::detail
