/* canonical_frame.h: the canonical configuration of a node-segment query (contactnn SPEC 4) and the check
 * of a network's training domain, for blocks of queries, in C99 that is also valid C++.
 *
 * One source for the network's inputs: lib/search compiles it into its network methods, and the exported
 * C header of a network embeds this text verbatim. Self-contained (only <math.h> and <string.h>); the include
 * guards are fixed, so two exported headers in one translation unit share one copy. A float network on
 * bilinear segments takes the float pass (cnn_canonicalise_domain_block_f): the same decisions, features in
 * float.
 *
 * This file includes its parts, one step each (the exported header inlines them in this order, each where it
 * is first included: lib/search/CMakeLists.txt):
 *   canonical_frame_base.h         compiler hints, status codes, max and min;
 *   canonical_frame_geometry.h     the frame and the segment's corners, defined once for double and float;
 *   canonical_frame_lane.h         one lane's canonical frame in double, and the block
 * (cnn_canonicalise_block); canonical_frame_ties.h         every canonical form of a query on a tie
 * (cnn_cf_forms); canonical_frame_domain.h       the training-domain test (struct cnn_domain,
 * cnn_domain_block); canonical_frame_float.h        one bilinear lane's frame and domain test in float
 * (cnn_cff_lane); canonical_frame_float_block.h  the float pass over blocks
 * (cnn_canonicalise_domain_block_f).
 *
 * What it computes is geometry::normalise (lib/geometry/affine_frame.hpp), the reference, written branch-free
 * per lane so that a compiler vectorises the loop over the lanes of a block:
 *  - invalid (status 4) when a coordinate (or, Gregory, a normal component) is not finite;
 *  - the symmetry of the square: canonical A is the first node nearest S (distances within 1e-12 relative
 *    plus 16 eps max|x| are a tie), then the mirror when |AD| > |AB| (on a tie: when S is nearer the line
 * AD);
 *  - the frame of SPEC 4 on the canonical A, B, D; z oriented so that z_S > 0 (with S on the plane: z_C > 0),
 *    a height within 1e-12 + 16 eps max|x| / |AB| counting as 0 (both on the plane: a z tie, no flip);
 *  - a flag for the lanes on a tie (another node as near S, |AB| = |AD| with S on the diagonal, a z tie),
 * whose other canonical forms cnn_cf_forms lists afterwards (the scalar path of ties, below);
 *  - degenerate (status 3) when that frame does not exist, when the segment is collapsed
 *    (geometry::is_degenerate_segment with the coordinates' own rounding as noise), or when a Gregory node
 *    normal is zero, in the segment plane, or the normals lie on both sides. Where the reference falls back
 * to another corner (a straight angle at the canonical A), the features are not those a network was trained
 *    on: that is degenerate here too, as it is for the reference's network methods.
 * Differences from the reference, all at the rounding level: lengths are compared through their squares
 * (two square roots per query instead of seventeen), divisions by a length are multiplications by its
 * reciprocal, and a node normal is rotated before it is normalised (its slopes n_x/n_z do not need the
 * length). A decision can therefore differ only for a configuration within a few ulps of a threshold.
 * Coordinates whose magnitude lies outside [1e-50, 1e50] (and normals outside [1e-50, 1e50] in length) are
 * first scaled by a power of two, which is exact, in a scalar pass, so that no square under- or overflows;
 * there, a difference of two coordinates that overflows makes the query degenerate.
 *
 * The loops over lanes vectorise with GCC at -O3 given -fno-math-errno (sqrt) and -fno-trapping-math (selects
 * over comparisons); without them the code is the same, scalar. Both change no result.
 *
 * Layout of a block of n lanes (n >= 1), structure of arrays, lane l of quantity k at [k * n + l]:
 *   in:    k = 0..14: ax ay az bx by bz cx cy cz dx dy dz sx sy sz (SPEC 6 order, world coordinates),
 *          Gregory also k = 15..26: nax nay naz ... ndz (node normals, any positive length);
 *   f:     features xc yc zc xd yd xs ys zs (+ Gregory pa qa pb qb pc qc pd qd), 8 or 16 rows;
 *   nrm:   Gregory only (else may be 0): the canonical node normals A..D in the canonical frame, 12 rows,
 *          oriented to the +z side but not normalised;
 *   info:  CNN_CF_INFO_ROWS = 6 rows: status (0 ok, 3 degenerate, 4 invalid), symmetry (rotation + 4 *
 * mirror: canonical node i is the caller's node ((mirror ? (4 - i) % 4 : i) + rotation) % 4), orientation (+1
 *          or -1: the caller's gap is orientation * canonical gap / scale), scale (1 / |AB|, canonical AB),
 *          a work row, and the tie code (1: a symmetry tie, + 2: a z tie; cnn_cf_needs_forms reads it).
 * Where the status is not 0, f and nrm hold unspecified finite or non-finite values.
 */
#ifndef CONTACTNN_CANONICAL_FRAME_H
#define CONTACTNN_CANONICAL_FRAME_H

/* Raised whenever what this file computes or its interface changes: an exported header checks that the copy
 * in force (the first one included in a translation unit) is the one it was generated with. */
#define CNN_CANONICAL_FRAME_VERSION 4

#include "search/canonical_frame_base.h"
#include "search/canonical_frame_domain.h"
#include "search/canonical_frame_float.h"
#include "search/canonical_frame_float_block.h"
#include "search/canonical_frame_geometry.h"
#include "search/canonical_frame_lane.h"
#include "search/canonical_frame_ties.h"

#endif /* CONTACTNN_CANONICAL_FRAME_H */
