// Step 2 of the scene study (scene_study.hpp): the scene's domain (dataset::sample_scene: its master segments
// deformed, the slave anywhere a contact can occur), and the one capture policy of every scene domain: the
// capture distance covers the deck's own slave nodes, kCaptureOverOffset times the largest offset of their
// pairs (|gap| / shortest edge). gen-configs --scene --sampling random, the face study and the scene study
// all widen their capture here.
#pragma once

#include <cstdint>
#include <vector>

#include "contact/scene.hpp"
#include "dataset/labelled_set.hpp"
#include "dataset/scene_sampling.hpp"
#include "eval/evaluation_set.hpp"
#include "projection/newton_projection.hpp"
#include "study/scene_study.hpp"

namespace contactnn::study {

/// The capture distance of a scene's domain is at least this many times the largest offset of the deck's own
/// pairs, so that the domain covers every slave node of the deck with room to spare.
inline constexpr double kCaptureOverOffset = 1.25;

/// max(capture, kCaptureOverOffset x deck_offset): the capture that covers the deck's own slave nodes.
[[nodiscard]] double widened_capture(double capture, double deck_offset);

/// domain.capture widened to widened_capture; `log` (if set) gets one line when it grows ("capture A -> B of
/// the shortest edge, to cover the deck's own slave nodes").
void widen_capture(dataset::SceneDomainOptions& domain, double deck_offset, const StudyLog& log);

/// The largest offset (|gap| / shortest edge) of the paper's nearest-node pairs (SPEC 7) of the scene's
/// corner slave nodes, far ones too.
[[nodiscard]] double nearest_node_offset(const contact::Scene& scene, SurfaceKind surface,
                                         const projection::ProjectionOptions& projection);

/// Appends the scene's master segments (4-node quadrilaterals, their nodes and node normals) as
/// dataset::sample_scene takes them.
void append_scene_segments(const contact::Scene& scene, std::vector<dataset::SceneSegment>& segments);

struct SceneDomain {
  dataset::SceneDomainOptions domain;  ///< the domain drawn (capture widened to the deck's offsets)
  double deck_offset = 0.0;            ///< largest |gap| / shortest edge of the deck's nearest-node pairs
  dataset::LabelledSet train;          ///< options.count configurations, seed
  dataset::LabelledSet heldout;        ///< count / heldout_divisor, seed + heldout_seed_offset
  eval::EvaluationSet heldout_set;     ///< the held-out sample as queries (its own frame)
  std::uint64_t heldout_seed = 0;
};

/// Step 2. InvalidArgument for a scene without master segments.
[[nodiscard]] SceneDomain sample_domain(const contact::Scene& scene, SurfaceKind surface,
                                        const SceneStudyOptions& options, const StudyLog& log = {});
/// Step 2 over several states of one pair (DomainStates::kHistory): the segments of every state are drawn
/// from (by area, as one scene's), and the capture covers the largest deck offset of any state. `states`
/// non-empty, each with master segments; with one state this is the overload above.
[[nodiscard]] SceneDomain sample_domain(const std::vector<const contact::Scene*>& states, SurfaceKind surface,
                                        const SceneStudyOptions& options, const StudyLog& log = {});

}  // namespace contactnn::study
