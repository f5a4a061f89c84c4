#include "study/scene_domain.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "study/scene_pairs.hpp"

namespace contactnn::study {

double widened_capture(double capture, double deck_offset) {
  return std::max(capture, kCaptureOverOffset * deck_offset);
}

void widen_capture(dataset::SceneDomainOptions& domain, double deck_offset, const StudyLog& log) {
  const double capture = widened_capture(domain.capture, deck_offset);
  if (capture == domain.capture) return;
  if (log) {
    char line[160];
    std::snprintf(line, sizeof line,
                  "capture %g -> %g of the shortest edge, to cover the deck's own slave nodes",
                  domain.capture, capture);
    log(line);
  }
  domain.capture = capture;
}

double nearest_node_offset(const contact::Scene& scene, SurfaceKind surface,
                           const projection::ProjectionOptions& projection) {
  contact::Scene corners = scene;
  keep_corner_slaves(corners);
  contact::SearchOptions nearest;
  nearest.search = contact::GlobalSearchKind::kNearestNode;
  nearest.surface = surface;
  nearest.projection = projection;
  return contact::largest_relative_offset(contact::search_scene(corners, nearest));
}

void append_scene_segments(const contact::Scene& scene, std::vector<dataset::SceneSegment>& segments) {
  segments.reserve(segments.size() + scene.master.segments.size());
  for (const auto& s : scene.master.segments) {
    dataset::SceneSegment segment;
    for (std::size_t i = 0; i < 4; ++i) {
      const auto node = static_cast<std::size_t>(s[i]);
      segment.nodes[i] = scene.master.positions[node];
      segment.normals[i] = scene.master_normals[node];
    }
    segments.push_back(segment);
  }
}

SceneDomain sample_domain(const contact::Scene& scene, SurfaceKind surface, const SceneStudyOptions& options,
                          const StudyLog& log) {
  return sample_domain(std::vector<const contact::Scene*>{&scene}, surface, options, log);
}

SceneDomain sample_domain(const std::vector<const contact::Scene*>& states, SurfaceKind surface,
                          const SceneStudyOptions& options, const StudyLog& log) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, !states.empty(), "sample_domain: no state of the scene");
  dataset::EnumerationOptions generator;
  generator.surface = surface;
  generator.seed = options.seed;
  SceneDomain out;
  std::vector<dataset::SceneSegment> segments;
  for (const contact::Scene* state : states) {
    const contact::Scene& scene = *state;
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, !scene.master.segments.empty(),
        "pair " << scene.pair << ": the master surface has no quadrilateral segment: no domain to sample");
    // The capture covers the pairs the local search serves (the surface search's on quad4 faces), or the
    // deck's own slave nodes: the offsets of the paper's nearest-node pairs (SPEC 7's slave nodes, corners
    // only), far ones too.
    const double offset = options.capture_pairs == "surface"
                              ? contact::largest_relative_offset(search_pairs(scene, surface).result)
                              : nearest_node_offset(scene, surface, generator.projection);
    out.deck_offset = std::max(out.deck_offset, offset);
    append_scene_segments(scene, segments);
  }
  out.domain = options.domain;
  widen_capture(out.domain, out.deck_offset, log);
  dataset::EnumerationSummary summary;
  out.train = dataset::sample_scene(segments, out.domain, generator, options.count, summary);
  out.heldout_seed = options.seed + options.heldout_seed_offset;
  generator.seed = out.heldout_seed;
  out.heldout =
      dataset::sample_scene(segments, out.domain, generator,
                            std::max<std::int64_t>(100, options.count / options.heldout_divisor), summary);
  out.heldout_set = eval::set_from_dataset(out.heldout, "heldout",
                                           "the scene's domain, seed " + std::to_string(out.heldout_seed),
                                           false, out.heldout_seed);
  return out;
}

}  // namespace contactnn::study
