// The global search on the project's example scenes (scripts/make-scene, written into the build tree by
// the example_scenes ctest fixture): the k-d tree search equals the brute-force one, also after random
// perturbations, and the labels agree with the independent oracle of test_support.hpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "io/inp_deck.hpp"
#include "scene_checks.hpp"

namespace contactnn::contact {
namespace {

// The oracle (dense grid + finite-difference Newton) is accurate to ~1e-10 on these segments; the
// issue's acceptance bounds.
constexpr double kBilinearOracleTol = 1e-9;
constexpr double kGregoryOracleTol = 1e-8;

struct ScenePair {
  std::string deck;
  int pair;
};

void PrintTo(const ScenePair& p, std::ostream* os) { *os << p.deck << " pair " << p.pair; }

const std::vector<ScenePair> kScenePairs = {{"hertz.inp", 0}, {"hertz.inp", 1}, {"cylinders.inp", 0},
                                            {"flat.inp", 0},  {"flat.inp", 1},  {"forming.inp", 0}};

std::filesystem::path scenes_dir() { return std::filesystem::path(CONTACTNN_EXAMPLE_SCENES_DIR); }

class ExampleScene : public ::testing::TestWithParam<std::tuple<ScenePair, SurfaceKind>> {
 protected:
  void SetUp() override {
    const auto& [scene_pair, kind] = GetParam();
    model_ = io::read_inp_deck(scenes_dir() / scene_pair.deck);
    scene_ = make_scene(model_, scene_pair.pair);
    options_.surface = kind;
    options_.search =
        GlobalSearchKind::kNearestNode;  // the paper's search; the surface search's test is below
  }
  [[nodiscard]] std::vector<NodeSegmentPair> search(const Scene& scene, NearestNodeMethod method) const {
    SearchOptions options = options_;
    options.nearest = method;
    return search_scene(scene, options).pairs;
  }
  mesh::ContactModel model_;
  Scene scene_;
  SearchOptions options_;
};

TEST_P(ExampleScene, TreeSearchEqualsBruteForceSearch) {
  const auto tree = search(scene_, NearestNodeMethod::kTree);
  const auto brute = search(scene_, NearestNodeMethod::kBruteForce);
  const auto c = testing::compare_searches(tree, brute);
  EXPECT_EQ(c.differences, 0) << c.first;
  long found = 0;
  for (const auto& p : tree) found += p.status == PairStatus::kFound;
  EXPECT_GT(found, static_cast<long>(tree.size()) / 2);
}

TEST_P(ExampleScene, TreeSearchEqualsBruteForceAfterRandomPerturbations) {
  // Slave nodes moved by up to half a master edge, master nodes by up to a tenth: other nearest nodes,
  // other candidates, other ties; the two searches must still agree pair for pair.
  std::mt19937_64 rng(67);
  double edge = 0.0;
  for (const auto& q : scene_.master.segments) {
    edge += (scene_.master.positions[static_cast<std::size_t>(q[1])] -
             scene_.master.positions[static_cast<std::size_t>(q[0])])
                .norm();
  }
  edge /= static_cast<double>(scene_.master.segments.size());
  for (int round = 0; round < 5; ++round) {
    Scene moved = scene_;
    std::uniform_real_distribution<double> slave_shift(-0.5 * edge, 0.5 * edge),
        master_shift(-0.1 * edge, 0.1 * edge);
    for (auto& p : moved.slave_positions) p += Vec3(slave_shift(rng), slave_shift(rng), slave_shift(rng));
    for (auto& p : moved.master.positions) p += Vec3(master_shift(rng), master_shift(rng), master_shift(rng));
    moved.master_normals = mesh::node_normals(moved.master);
    // Some slave nodes put exactly on master nodes: distance 0, and ties between segments.
    for (std::size_t i = 0; i < moved.slave_positions.size(); i += 5) {
      moved.slave_positions[i] = moved.master.positions[i % moved.master.positions.size()];
    }
    const auto c = testing::compare_searches(search(moved, NearestNodeMethod::kTree),
                                             search(moved, NearestNodeMethod::kBruteForce));
    EXPECT_EQ(c.differences, 0) << "round " << round << ": " << c.first;
  }
}

TEST_P(ExampleScene, LabelsAgreeWithTheIndependentOracle) {
  const auto pairs = search(scene_, NearestNodeMethod::kTree);
  const auto c = testing::compare_with_oracle(pairs, options_.surface);
  const double tol = options_.surface == SurfaceKind::kGregory ? kGregoryOracleTol : kBilinearOracleTol;
  EXPECT_LE(c.max_difference, tol) << "worst slave " << c.worst_slave;
  EXPECT_EQ(c.nearer_than_label, 0);
  EXPECT_GT(c.compared, 0);
}

TEST_P(ExampleScene, ReportedNodeOrderIsNearestNodeFirstThenCounterClockwiseAboutTheOutwardNormal) {
  const auto pairs = search(scene_, NearestNodeMethod::kTree);
  for (const auto& p : pairs) {
    if (p.status != PairStatus::kFound) continue;
    const auto& x = p.config.nodes;
    // A is a nearest master node (of all the nodes of segments, so of the segment's too; a quadratic face's
    // mid-side nodes are the surface search's, never the paper's nearest node).
    for (int n = 0; n < scene_.master.node_count(); ++n) {
      if (scene_.master.segments_of(n).empty()) continue;
      const Vec3& other = scene_.master.positions[static_cast<std::size_t>(n)];
      ASSERT_LE((p.config.slave - x[0]).squaredNorm(), (p.config.slave - other).squaredNorm()) << p.slave_id;
    }
    // The same cyclic order as the outward segment (B - A) x (D - A) of the surface mesh.
    const auto& q = scene_.master.segments[static_cast<std::size_t>(p.segment)];
    int k = 0;
    while (q[static_cast<std::size_t>(k)] != p.nodes[0]) ++k;
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(p.nodes[static_cast<std::size_t>(i)], q[static_cast<std::size_t>((k + i) % 4)]);
  }
}

TEST_P(ExampleScene, SearchIsTheSameForAnyThreadCount) {
  // OpenMP's schedule must not change a result: compare one thread with the default.
  const auto many = search(scene_, NearestNodeMethod::kTree);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = search(scene_, NearestNodeMethod::kTree);
  omp_set_num_threads(saved);
  EXPECT_EQ(testing::compare_searches(many, one).differences, 0);
}

TEST_P(ExampleScene, SurfaceSearchTreeEqualsEveryFaceAndNeverMissesTheNearestNodesSegment) {
  SearchOptions options = options_;
  options.search = GlobalSearchKind::kSurface;
  const auto tree = search_scene(scene_, options).pairs;
  options.brute_force_faces = true;
  const auto every = search_scene(scene_, options).pairs;
  const auto paper = search(scene_, NearestNodeMethod::kTree);
  ASSERT_EQ(tree.size(), every.size());
  for (std::size_t i = 0; i < tree.size(); ++i) {
    ASSERT_EQ(tree[i].status, every[i].status) << "slave " << tree[i].slave_id;
    if (tree[i].status != PairStatus::kFound) continue;
    EXPECT_EQ(tree[i].segment, every[i].segment) << "slave " << tree[i].slave_id;
    EXPECT_EQ(tree[i].label.gap, every[i].label.gap) << "slave " << tree[i].slave_id;
    // The nearest point of the whole surface is never farther than the paper's pair's point inside its
    // segment (where both search the same surfaces: the paper's search takes a quad8 by its corners).
    if (paper[i].status == PairStatus::kFound && paper[i].label.status == Status::kOk &&
        scene_.master.face_type(tree[i].segment) != mesh::FaceType::kQuad8 &&
        scene_.master.face_type(paper[i].segment) != mesh::FaceType::kQuad8) {
      EXPECT_LE(std::abs(tree[i].label.gap), std::abs(paper[i].label.gap) * (1.0 + 1e-9) + 1e-12)
          << "slave " << tree[i].slave_id;
    }
  }
}

std::string name(const ::testing::TestParamInfo<std::tuple<ScenePair, SurfaceKind>>& info) {
  std::string deck = std::get<0>(info.param).deck;
  deck = deck.substr(0, deck.find('.'));
  return deck + "_pair" + std::to_string(std::get<0>(info.param).pair) + "_" +
         std::string(to_string(std::get<1>(info.param)));
}

INSTANTIATE_TEST_SUITE_P(Scenes, ExampleScene,
                         ::testing::Combine(::testing::ValuesIn(kScenePairs),
                                            ::testing::Values(SurfaceKind::kBilinear, SurfaceKind::kGregory)),
                         name);

}  // namespace
}  // namespace contactnn::contact
