// The domain a scene requires (issue "Scenes"): its own master segments, deformed by a stated amount, with
// the slave node anywhere a contact can occur on them; random configurations of it, labelled by the
// reference projection. A network trained on it models only what the scene needs.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dataset/enumeration.hpp"
#include "dataset/labelled_set.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::dataset {

/// A master segment of a scene in world coordinates: nodes counter-clockwise about the outward normal
/// (SPEC 7), and unit node normals (Eq 26; used for Gregory).
struct SceneSegment {
  std::array<geometry::Vec3, 4> nodes;
  std::array<geometry::Vec3, 4> normals;
};

/// How far the scene's domain reaches beyond its segments as they are. Lengths are fractions of each
/// segment's shortest edge e, so the domain scales with the mesh. Every field is a gen-configs key.
struct SceneDomainOptions {
  /// Each node moves by a random vector uniform in the ball of radius deformation * e: the segment shapes a
  /// time step of a deforming mesh can show (0.1: a 10% strain of the shortest edge, beyond what an
  /// explicit step does, so the network holds over many steps).
  double deformation = 0.1;
  /// The slave node lies within capture * e of the (deformed) facet along its normal, on either side: gaps
  /// and penetrations a contact search captures. 0.5: half the shortest edge, above the node offsets of the
  /// decks this was tried on (at most ~0.1 e for nodes in contact) and far above a step's motion.
  double capture = 0.5;
  /// Gregory: each node normal is tilted from the scene's by an angle whose tangent is uniform in
  /// [0, normal_tilt_tangent) (deformation turns normals too; 0.1 is ~6 degrees).
  double normal_tilt_tangent = 0.1;
  /// Fraction of foot points placed on the segment's boundary: half of them at a node, half on an edge
  /// (the other coordinate uniform). Matching meshes put slave nodes exactly there (on a master node, over a
  /// master edge), where the coordinates are extreme and a uniform sample seldom goes. 0.2.
  double boundary_fraction = 0.2;
  /// S passes the segment test of Eqs 3-6 at the segment's node nearest it, as the paper's nearest-node pairs
  /// do (SPEC 7); the domain's filters then require it. Off: S anywhere over the facet within the capture, as
  /// the surface search (SPEC 9) pairs a slave node with a face: a pair inside a curved Gregory face need not
  /// pass the test (on forming-stroke's history 3 to 6 of 57 to 66 such pairs did not, every one of them out
  /// of a domain drawn with the test). scene-study turns it off for a history study (--segment-test auto).
  bool segment_test = true;
};

/// `count` configurations of the scene's domain: row i draws (stream (seed, i)) a segment with probability
/// proportional to its area, deforms it (SceneDomainOptions), places S along the facet normal over a foot
/// point uniform in (xi, eta) (or on the boundary, boundary_fraction), keeps it when it could be a pair of
/// the global search (SPEC 7): S passes the segment test of Eqs 3-6 at the segment's node nearest it
/// (domain.segment_test; else any S); labels it with options.projection (kind options.surface) and keeps it
/// when the projection lies inside (status ok), as the paper's sets. The features and labels are canonical
/// (SPEC 4). The set's `filters` describe the domain drawn: limits, interior angles and node-normal tilts of
/// the accepted rows, widened by 1%. options.filters and the grid sizes are not used. Throws InvalidArgument
/// for no segment, count < 1, or a domain no draw lands in.
[[nodiscard]] LabelledSet sample_scene(const std::vector<SceneSegment>& segments,
                                       const SceneDomainOptions& domain, const EnumerationOptions& options,
                                       std::int64_t count, EnumerationSummary& summary,
                                       const ProgressFn& progress = {});

}  // namespace contactnn::dataset
