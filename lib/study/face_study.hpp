// The scene study on quadratic master faces (issue 28): for one contact pair of a deck whose master surface
// has tri6 or quad8 faces, every method of search::FaceSearch measured on the scene's domain, a scene network
// of each size trained in memory until one reaches the target, and the fastest method that reaches it chosen;
// a network only where one pays. scene-study --face runs it (apps/scene-study); the quad4 study is
// scene_study.hpp.
//
// Steps, one process, one reading of the deck:
//  1. face_pairs: the surface search (SPEC 9) of every slave node; the pairs whose point lies inside a face
//  of
//     the kind (location face) are the local search's work and judge the methods (the deck's own pairs).
//  2. sample_face_domain: the scene's domain: a face of the kind drawn (area-weighted), each node moved by a
//     random vector in the ball of radius deformation x e (e its shortest corner edge), a foot point in the
//     face (or on its boundary, boundary_fraction), S along the normal there within capture x e on either
//     side; labelled by the closest point on the true face (projection::closest_point_on_quadratic_triangle /
//     _serendipity_quad) and kept when that lies inside the face. The capture is at least `capture`, widened
//     to 1.25 x the largest |gap| / e of the deck's pairs. A training sample and a held-out one (another
//     seed).
//  3. train_face_networks: each size of `sizes` in turn (hidden layers, smallest first), online back-
//     propagation with momentum on the canonical features (search::face_canonical_form), the best validation
//     epoch kept; the first whose held-out mean |error| is within margin x target ends the round.
//  4. measure: every method (closed form, newton:K, newton, hybrids, each network alone and with Newton
//  steps)
//     on the held-out sample (accuracy, batched 1-thread time: the fastest of the timed passes) and on the
//     deck's pairs (accuracy); the choice: the fastest method whose held-out effective mean |error| (a
//     failure counts as one domain width) is at most margin x target.
//  5. The report (face_study_markdown) and the chosen network's file (io::write_face_network).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "core/log.hpp"
#include "mlp/network.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"

namespace contactnn::study {

/// Every policy default of the face study (scene-study --face takes the same names).
struct FaceStudyOptions {
  /// Node moves, x the face's shortest corner edge. 0.02, not the quad4 study's 0.1: a quadratic face's shape
  /// is its mid-side nodes' offsets from their chords, and 0.1 e moves them by as much as the decks' own
  /// curvature puts them there. On tet-press (tri6) and tubes-press (quad8) at 0.1 no network of at most two
  /// layers of 48 came within 0.005 on the deck's own pairs (0.0123 / 0.027 for 48x48); at 0.02 both did
  /// (0.0023, 0.0029), and the decks' masters (100 times stiffer than their slaves) deform far less between
  /// increments.
  double deformation = 0.02;
  double capture = 0.5;            ///< S within this x e of the face at least (SceneDomainOptions')
  double boundary_fraction = 0.2;  ///< feet on a node or an edge (SceneDomainOptions')
  std::int64_t count = 60000;      ///< training sample (train and validation)
  std::int64_t heldout = 15000;    ///< held-out sample, seed + 1000
  std::uint64_t seed = 1;
  /// Mean |error| to reach, local units: 0.005 (issue 28's, as the bilinear scene target in xi units).
  double target = 0.005;
  double margin = 0.8;  ///< a method reaches the target when its held-out error is at most margin x target
  /// Hidden layers of each size tried, smallest first (at most two layers of 48: issue 28's bound).
  std::vector<std::vector<int>> sizes = {{16}, {32}, {48}, {48, 48}};
  int epochs = 400;  ///< online passes over the training patterns per size
  double learning_rate = 0.01;
  double learning_rate_final = 0.001;  ///< decayed geometrically to this over the epochs
  double momentum = 0.9;
  double u0 = 2.0;
  double input_quantile = 0.005;
  double validation_fraction = 0.2;  ///< of count
  /// Methods without a network, comma-separated search::Method names.
  std::string methods =
      "closed_form,newton:1,newton:2,newton:3,newton:4,newton:5,newton,closed_form+newton:1,closed_form+"
      "newton:2,"
      "closed_form+newton:3";
  /// With each trained network.
  std::string network_methods = "network,network+newton:1,network+newton:2";
  std::int64_t timing_queries = 20000;
  int timing_passes = 11;
  int threads = 0;  ///< sampling, labelling and accuracy (0: OpenMP's default); training runs on one thread
};

/// Progress lines of the face study (core/log.hpp).
using FaceStudyLog = ProgressLog;

/// Queries of one face kind: world rows for FaceSearch (face_raw_columns values each) and the reference's
/// local coordinates in the caller's order.
struct FaceQueries {
  search::FaceKind kind = search::FaceKind::kTri6;
  std::vector<double> raw;
  std::vector<double> label;  ///< 2 per query
  [[nodiscard]] std::size_t size() const { return label.size() / 2; }
};

/// Step 1: the deck's pairs inside faces of `kind`, and the largest |gap| / e among them.
struct FacePairs {
  FaceQueries pairs;
  std::vector<long> slave_ids;
  long slave_nodes = 0, on_kind = 0;  ///< all slave nodes; those whose face is of `kind` (any location)
  int faces = 0;                      ///< faces of `kind` on the master surface
  double largest_offset = 0.0;        ///< max |gap| / (shortest corner edge of the face)
};
[[nodiscard]] FacePairs face_pairs(const contact::Scene& scene, search::FaceKind kind);

/// Step 2: `count` configurations of the scene's domain (rows drawn from (seed, row): any thread count gives
/// the same set). `capture` is the resolved one.
[[nodiscard]] FaceQueries sample_face_domain(const contact::Scene& scene, search::FaceKind kind,
                                             const FaceStudyOptions& options, double capture,
                                             std::int64_t count, std::uint64_t seed);

/// The general domain of a face type, paper-like (Section 5's bilinear domain carried to quadratic faces;
/// docs/library.md "Faces"): in the canonical frame A = (0, 0, 0), B = (1, 0, 0); the last corner (C of a
/// triangle, D of a quad) at a distance in [0.5, 1] from A (|AD| <= |AB|, as the paper's) and an angle at A
/// in [60, 120] degrees; a quad's C at B + D moved by up to 0.3 in each coordinate (warped out of plane by up
/// to 0.3, as the paper's z of C); each mid-side node at its chord's midpoint moved by up to `curvature` x
/// the edge length in each coordinate; S over a foot point in the face (boundary_fraction on nodes and edges)
/// at a height within +-0.3 (the paper's z of S), kept when its closest point on the true face lies inside
/// it.
[[nodiscard]] FaceQueries sample_general_face_domain(search::FaceKind kind, const FaceStudyOptions& options,
                                                     double curvature, std::int64_t count,
                                                     std::uint64_t seed);

/// Trains one network of `hidden` layers on `train` (canonical features, targets the corrections to the
/// corner closed form) and measures it on `heldout` (step 3 of the study for one size).
struct FaceNetworkResult;
[[nodiscard]] FaceNetworkResult train_face_network(search::FaceKind kind, const std::vector<int>& hidden,
                                                   const FaceQueries& train, const FaceQueries& heldout,
                                                   const FaceStudyOptions& options,
                                                   const FaceStudyLog& log = {});

struct FaceNetworkResult {
  std::string name;  ///< e.g. "20-48-2"
  std::vector<int> hidden;
  std::shared_ptr<const mlp::Network<float>> network;
  std::shared_ptr<const search::FaceNetwork> model;
  std::vector<double> feature_min, feature_max;
  int epochs = 0, best_epoch = 0;
  double heldout_error = 0.0;  ///< the larger coordinate's mean |error|, network alone
  double seconds = 0.0;
};

struct FaceMethodResult {
  std::string name;    ///< "closed_form", "network+newton:1[20-48-2]"
  std::string method;  ///< the search::Method name
  int network = -1;    ///< index into FaceStudy::networks
  double heldout_mean = 0.0, heldout_effective = 0.0, heldout_max = 0.0;
  long heldout_failures = 0;  ///< status other than ok or outside where the label is inside
  double pairs_mean = 0.0, pairs_max = 0.0;
  long pairs_failures = 0;
  double batched_ns = 0.0;  ///< held-out sample, 1 thread, fastest pass
  bool reaches = false;
};

struct FaceStudy {
  search::FaceKind kind = search::FaceKind::kTri6;
  FaceStudyOptions options;
  FacePairs pairs;
  double capture = 0.0;  ///< resolved, x e (a scene's study)
  double general_curvature =
      -1.0;  ///< the general domain's mid-side offsets (run_general_face_study), else < 0
  std::size_t train_count = 0, heldout_count = 0;
  std::vector<FaceNetworkResult> networks;
  std::vector<FaceMethodResult> methods;
  int chosen = -1;  ///< index into methods: the fastest that reaches margin x target (-1: none; the report
                    ///< then names the most accurate)
  double seconds = 0.0;
};

/// Steps 1-4. InvalidArgument for tri3 (its closed form is exact: nothing to study), a scene without faces of
/// `kind` or without pairs inside them, or options out of range.
[[nodiscard]] FaceStudy run_face_study(const contact::Scene& scene, search::FaceKind kind,
                                       const FaceStudyOptions& options, const FaceStudyLog& log = {});

/// Steps 2-4 on the general domain of `kind` (sample_general_face_domain) instead of a scene's: no pairs.
/// What scene-study --face K --general runs to make the shipped general face networks (data/weights).
[[nodiscard]] FaceStudy run_general_face_study(search::FaceKind kind, const FaceStudyOptions& options,
                                               double curvature, const FaceStudyLog& log = {});

/// The report: the scene, the sample, the networks, every method on the held-out sample and on the deck's
/// pairs, the choice, and the fastest method at each accuracy level (the frontier of the scene).
[[nodiscard]] std::string face_study_markdown(const FaceStudy& study, const std::string& deck, int pair);

}  // namespace contactnn::study
