// Step 1 of the scene study (scene_study.hpp): the deck's own pairs, found by the surface search (SPEC 9) and
// labelled by the reference, as evaluation sets and as the pairs CSV that gen-configs --scene writes too
// (SPEC 7, 9 and 10 columns: one row writer for both programs).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "core/conventions.hpp"
#include "dataset/labeller.hpp"
#include "eval/evaluation_set.hpp"

namespace contactnn::study {

/// The deck's own pairs (step 1).
struct ScenePairs {
  contact::SceneResult result;      ///< the surface search, one pair per slave node
  std::array<long, 3> locations{};  ///< pairs by Location: face, edge, vertex
  long quad4 = 0;                   ///< pairs on a 4-node quadrilateral (the SPEC 7 configurations)
  eval::EvaluationSet face;         ///< quad4 pairs with location face: what judges the methods
  eval::EvaluationSet quad4_pairs;  ///< every quad4 pair, edges and vertices included (for comparison)
};

/// The search options of search_pairs: the surface search (SPEC 9) on `surface`, every other option its
/// default (the exact search).
[[nodiscard]] contact::SearchOptions pairs_search_options(SurfaceKind surface);

/// The surface search over the scene's slave nodes with the reference labels (pairs_search_options).
[[nodiscard]] ScenePairs search_pairs(const contact::Scene& scene, SurfaceKind surface);

/// The pairs as gen-configs --scene writes them (SPEC 7 and 9 columns): the text of DIR/pairs.csv.
[[nodiscard]] std::string pairs_csv(const contact::Scene& scene, const ScenePairs& pairs,
                                    SurfaceKind surface);

/// The columns of a pairs CSV: `slave,a,b,c,d`, the raw columns (SPEC 6, node normals for Gregory), the label
/// (`xi,eta` or `u,v`, `status,gap,iterations`); `increment` first with `increment`; SPEC 9's
/// `location,px,py,pz,face_type,nodes` last with `surface_search`.
struct PairsCsvLayout {
  SurfaceKind surface = SurfaceKind::kBilinear;
  bool increment = false;  ///< an `increment` column first (gen-configs --increment all, SPEC 10)
  bool surface_search =
      true;  ///< the surface search's columns (SPEC 9); false: the nearest-node search's pairs
};

[[nodiscard]] std::vector<std::string> pairs_csv_header(const PairsCsvLayout& layout);

/// Appends the CSV row of `pair` of `scene` to `text` (io::append_csv_row): node ids, world coordinates
/// (round-trip exact), the label, the closest point. A pair without a segment keeps every field empty but
/// `slave` and `status` (no_segment). With the surface search, a face that is not a quad4 has no SPEC 7
/// configuration: its own local coordinates go in the coordinate columns and the raw columns stay empty.
/// `increment` is the increment's number (written with layout.increment only).
void append_pair_row(std::string& text, const contact::Scene& scene, const contact::NodeSegmentPair& pair,
                     const PairsCsvLayout& layout, int increment = 0);

/// A label as the CSV's fields xi,eta (u,v),status,gap,iterations: values only where converged (ok or
/// outside), a zero written 0 (never -0); a no_segment label keeps every field but the status empty.
[[nodiscard]] std::vector<std::string> label_csv_fields(const dataset::Label& label);

/// The paper's nearest-node search keeps SPEC 7's slave nodes: an element surface's face corners, without the
/// mid-side nodes of quadratic faces that the surface search adds (SPEC 9; mesh::SlaveNodes).
void keep_corner_slaves(contact::Scene& scene);

}  // namespace contactnn::study
