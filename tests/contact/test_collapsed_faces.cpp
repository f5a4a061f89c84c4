// Faces collapsed by coincident nodes (issue 39, failure 1; mesh::build_surface_mesh's "Collapsed faces"): a
// wedge written as a C3D8 (distinct ids on one point, or repeated ids) and a quadratic wedge written as a
// C3D20, read from the decks in tests/contact/data, searched by contact::surface_search and compared with an
// independent closest point of the true surface (true_surface_oracle.hpp): the collapsed faces are the
// triangles they are, the faces collapsed to a line are skipped and counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "contact/surface_search.hpp"
#include "io/inp_deck.hpp"
#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "true_surface_oracle.hpp"

namespace contactnn::contact {
namespace {

using testing::TrueFace;

// The decks are of unit size: the search's closest points are exact to rounding, the oracle's to its compass
// search's last step (1e-14 in parameters).
constexpr double kDistanceTol = 1e-9;

mesh::ContactModel read_deck(const std::string& name) {
  return io::read_inp_deck(std::string(CONTACTNN_SOURCE_DIR) + "/tests/contact/data/" + name);
}

/// The deck's position of node `id`.
Vec3 node(const mesh::ContactModel& model, long id) { return model.mesh.position(model.mesh.find_node(id)); }

/// The unit wedge of the C3D8 decks (x, y >= 0, x + y <= 1, 0 <= z <= 1) face by face, from its six corners:
/// the bottom and top triangles and the three sides (S5 of the C3D8, collapsed to the edge x = 0, y = 1, is
/// not a face).
std::vector<TrueFace> linear_wedge(const mesh::ContactModel& m) {
  return {testing::true_tri3({node(m, 1), node(m, 2), node(m, 3)}, 1),
          testing::true_tri3({node(m, 5), node(m, 6), node(m, 7)}, 2),
          testing::true_quad4({node(m, 1), node(m, 5), node(m, 6), node(m, 2)}, 3),
          testing::true_quad4({node(m, 2), node(m, 6), node(m, 7), node(m, 3)}, 4),
          testing::true_quad4({node(m, 3), node(m, 7), node(m, 5), node(m, 1)}, 6)};
}

/// Every slave node of pair 0 searched (bilinear) and compared with the oracle: the same distance, a point on
/// the true surface. Returns the pairs.
std::vector<NodeSegmentPair> check_against_oracle(const Scene& scene, const std::vector<TrueFace>& truth) {
  SearchOptions options;
  options.capture_distance = 10.0;  // every slave node of the decks has a point
  const std::vector<NodeSegmentPair> pairs =
      surface_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, options);
  int wrong = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Vec3& s = scene.slave_positions[i];
    const testing::OraclePoint expected = testing::closest_point_on_true_surface(truth, s);
    const NodeSegmentPair& p = pairs[i];
    EXPECT_EQ(p.status, PairStatus::kFound) << "slave " << p.slave_id;
    if (p.status != PairStatus::kFound) continue;
    const double distance = (s - p.point).norm();
    const double off_surface = testing::closest_point_on_true_surface(truth, p.point).distance;
    if (std::abs(distance - expected.distance) > kDistanceTol || off_surface > kDistanceTol) {
      if (++wrong <= 5) {
        ADD_FAILURE() << "slave " << p.slave_id << " at (" << s.transpose() << "): point ("
                      << p.point.transpose() << ") on face " << p.segment << " at " << distance << ", "
                      << off_surface << " off the true surface; the true closest point ("
                      << expected.point.transpose() << ") at " << expected.distance << " on face S"
                      << truth[static_cast<std::size_t>(expected.face)].tag;
      }
    }
    EXPECT_NEAR(std::abs(p.label.gap), distance, kDistanceTol) << "slave " << p.slave_id;
  }
  EXPECT_EQ(wrong, 0) << "of " << pairs.size() << " slave nodes";
  return pairs;
}

/// The pair of slave node `id`.
const NodeSegmentPair& pair_of(const Scene& scene, const std::vector<NodeSegmentPair>& pairs, long id) {
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (scene.slave_ids[i] == id) return pairs[i];
  }
  throw std::runtime_error("no slave node " + std::to_string(id));
}

/// The node: 0.0278 above the bottom triangle, inside the element, gets the triangle's point, under
/// either surface (the triangles are flat under --surface gregory too), with a negative gap (it penetrates).
void expect_bottom_point(const Scene& scene) {
  for (const SurfaceKind surface : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    SearchOptions options;
    options.surface = surface;
    const auto pairs =
        surface_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, options);
    const NodeSegmentPair& p = pair_of(scene, pairs, 101);
    ASSERT_EQ(p.status, PairStatus::kFound);
    EXPECT_LT((p.point - Vec3(0.25, 0.25, 0.0)).norm(), 1e-12)
        << to_string(surface) << ": " << p.point.transpose();
    EXPECT_NEAR(p.label.gap, -0.0278, 1e-12) << to_string(surface);
    EXPECT_EQ(scene.master.face_of(p.segment).face, 1) << to_string(surface);
    const mesh::FaceType type = scene.master.face_type(p.segment);
    EXPECT_TRUE(type == mesh::FaceType::kTri3 || type == mesh::FaceType::kTri6) << mesh::to_string(type);
  }
}

/// The scene of a linear wedge written as a C3D8 (`model`): searched as the wedge (its bottom point, the
/// oracle's answers), S1 and S2 triangles, S3, S4, S6 segments, S5 a line.
Scene expect_linear_wedge(const mesh::ContactModel& model) {
  Scene scene = make_scene(model, 0);
  expect_bottom_point(scene);
  check_against_oracle(scene, linear_wedge(model));
  EXPECT_EQ(scene.master.segments.size(), 3u);
  EXPECT_EQ(scene.master.extra_faces.size(), 2u);
  EXPECT_EQ(scene.master.skipped_faces,
            (std::map<std::string, int>{{"C3D8 face collapsed to a line", 1},
                                        {"C3D8 face collapsed to a triangle", 2}}));
  return scene;
}

TEST(CollapsedFaces, WedgeAsC3D8WithCoincidentNodesIsSearchedAsItsTrianglesAndQuadrilaterals) {
  const mesh::ContactModel model = read_deck("wedge-c3d8-coincident.inp");
  const Scene scene = expect_linear_wedge(model);
  for (int f = 3; f < std::min(5, scene.master.face_count()); ++f)
    EXPECT_EQ(scene.master.face_type(f), mesh::FaceType::kTri3);
  // Node 4 is node 3 on every face, 8 is 7; neither is a surface node.
  EXPECT_EQ(scene.master.node_ids, (std::vector<long>{1, 2, 3, 5, 6, 7}));
  ASSERT_EQ(scene.master.merged_nodes.size(), 2u);
  EXPECT_EQ(model.mesh.node_id(scene.master.merged_nodes[0][0]), 4);
  EXPECT_EQ(model.mesh.node_id(scene.master.merged_nodes[0][1]), 3);
  EXPECT_EQ(model.mesh.node_id(scene.master.merged_nodes[1][0]), 8);
  EXPECT_EQ(model.mesh.node_id(scene.master.merged_nodes[1][1]), 7);
}

TEST(CollapsedFaces, WedgeAsC3D8WithRepeatedNodeIdsKeepsItsTwoTriangles) {
  const Scene scene = expect_linear_wedge(read_deck("wedge-c3d8-repeated.inp"));
  EXPECT_TRUE(scene.master.merged_nodes.empty());
}

TEST(CollapsedFaces, QuadraticWedgeAsC3D20IsSearchedAsItsSixNodeTrianglesAndQuad8s) {
  const mesh::ContactModel model = read_deck("wedge-c3d20-coincident.inp");
  const Scene scene = make_scene(model, 0);
  const auto n = [&](long id) { return node(model, id); };
  const std::vector<TrueFace> truth = {
      testing::true_tri6({n(1), n(3), n(4), n(10), n(11), n(12)}, 1),
      testing::true_tri6({n(5), n(7), n(8), n(14), n(15), n(16)}, 2),
      testing::true_quad8({n(2), n(6), n(7), n(3), n(18), n(14), n(19), n(10)}, 4),
      testing::true_quad8({n(3), n(7), n(8), n(4), n(19), n(15), n(20), n(11)}, 5),
      testing::true_quad8({n(4), n(8), n(5), n(1), n(20), n(16), n(17), n(12)}, 6)};
  expect_bottom_point(scene);
  check_against_oracle(scene, truth);
  // S1 and S2 tri6 (corners 1, 4, 3 and 5, 7, 8 with the mid-side nodes of their other edges), S4, S5, S6
  // quad8 segments, S3 a line.
  EXPECT_EQ(scene.master.segments.size(), 3u);
  EXPECT_EQ(scene.master.extra_faces.size(), 2u);
  for (int f = 0; f < scene.master.face_count(); ++f) {
    EXPECT_EQ(scene.master.face_type(f), f < 3 ? mesh::FaceType::kQuad8 : mesh::FaceType::kTri6) << f;
  }
  EXPECT_EQ(scene.master.skipped_faces,
            (std::map<std::string, int>{{"C3D20 face collapsed to a line", 1},
                                        {"C3D20 face collapsed to a triangle", 2}}));
}

/// A hexahedron collapsed into a pyramid (its top 5-8 on one point) and into a wedge (edge 3-4 and 7-8), by
/// coincident coordinates: the faces without area are counted, by kind, and are no faces of the search.
TEST(CollapsedFaces, FacesCollapsedToALineOrAPointAreSkippedAndCounted) {
  mesh::SolidMesh m;
  const std::vector<Vec3> x = {{0, 0, 0},     {1, 0, 0},     {1, 1, 0},     {0, 1, 0},
                               {0.5, 0.5, 1}, {0.5, 0.5, 1}, {0.5, 0.5, 1}, {0.5, 0.5, 1}};
  std::vector<int> nodes;
  for (std::size_t i = 0; i < x.size(); ++i) nodes.push_back(m.add_node(static_cast<long>(i) + 1, x[i]));
  m.add_element(1, mesh::element_type("C3D8R"), nodes);
  std::vector<mesh::ElementFace> faces;
  for (int f = 1; f <= 6; ++f) faces.push_back({0, f});
  const mesh::SurfaceMesh s = mesh::build_surface_mesh(m, faces);
  // S1 the base; S2 (the apex) a point; S3..S6 triangles (each with one edge on the apex).
  EXPECT_EQ(s.segments.size(), 1u);
  EXPECT_EQ(s.extra_faces.size(), 4u);
  EXPECT_EQ(s.skipped_faces, (std::map<std::string, int>{{"C3D8R face collapsed to a point", 1},
                                                         {"C3D8R face collapsed to a triangle", 4}}));
  EXPECT_EQ(s.node_ids, (std::vector<long>{1, 2, 3, 4, 5}));
  // Deformed: the deck's coordinates decide, not the moved ones (every increment of a history has the same
  // faces). The apex's nodes moved apart do not give the top an area.
  for (int i = 5; i < 8; ++i) m.set_position(i, Vec3(0.5 + 0.1 * i, 0.5, 1.0));
  const mesh::SurfaceMesh moved = mesh::build_surface_mesh(m, faces);
  EXPECT_EQ(moved.skipped_faces, s.skipped_faces);
  EXPECT_EQ(moved.face_count(), s.face_count());
}

}  // namespace
}  // namespace contactnn::contact
