// Tests for lib/mesh: element types and face tables, outward face orientation, surface meshes (adjacency,
// skipped faces) and the node normals of Eq 26.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <set>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "geometry/node_normals.hpp"
#include "mesh/contact_model.hpp"
#include "mesh/element_type.hpp"
#include "mesh/grid_surface.hpp"
#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "test_support.hpp"

namespace contactnn::mesh {
namespace {

// Unit normals through a few cross products and one normalisation: rounding only.
constexpr double kNormalTol = 1e-12;

TEST(ElementType, SegmentFacesExactlyForTheFiveTypesOfSpec7) {
  for (const char* name : {"C3D8", "c3d8r", "C3D8I", "C3D20", "C3d20r"}) {
    EXPECT_TRUE(element_type(name).has_segment_faces) << name;
    EXPECT_EQ(element_type(name).shape, ElementShape::kHexahedron) << name;
  }
  for (const char* name : {"C3D8H", "C3D20RH", "C3D6", "C3D15", "C3D4", "C3D10", "S4R", "B31"}) {
    EXPECT_FALSE(element_type(name).has_segment_faces) << name;
  }
  EXPECT_EQ(element_type("C3D20R").node_count, 20);
  EXPECT_EQ(element_type("C3D8I").node_count, 8);
  EXPECT_EQ(element_type("C3D6").node_count, 6);
  EXPECT_EQ(element_type("C3D15").node_count, 15);
  EXPECT_EQ(element_type("C3D4").node_count, 4);
  EXPECT_EQ(element_type("C3D10M").node_count, 10);
  EXPECT_EQ(element_type("S4R").node_count, 0);
  EXPECT_EQ(element_type("S4R").shape, ElementShape::kOther);
}

TEST(ElementType, HexahedronFacesAreSpec7sTable) {
  // SPEC 7, written out: S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1.
  const int expected[6][4] = {{1, 2, 3, 4}, {5, 8, 7, 6}, {1, 5, 6, 2},
                              {2, 6, 7, 3}, {3, 7, 8, 4}, {4, 8, 5, 1}};
  for (int f = 1; f <= 6; ++f) {
    const auto corners = face_corner_indices(ElementShape::kHexahedron, f);
    ASSERT_EQ(corners.size(), 4u);
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(corners[static_cast<std::size_t>(k)] + 1, expected[f - 1][k]) << "S" << f;
  }
  EXPECT_TRUE(face_corner_indices(ElementShape::kHexahedron, 7).empty());
  EXPECT_TRUE(face_corner_indices(ElementShape::kHexahedron, 0).empty());
  EXPECT_EQ(face_corner_indices(ElementShape::kWedge, 1).size(), 3u);
  EXPECT_EQ(face_corner_indices(ElementShape::kWedge, 3).size(), 4u);
  EXPECT_EQ(face_corner_indices(ElementShape::kTetrahedron, 4).size(), 3u);
  EXPECT_TRUE(face_corner_indices(ElementShape::kOther, 1).empty());
}

/// A hexahedron numbered as the manuals require (1-4 counter-clockwise seen from 5-8's side), a unit cube
/// with every corner moved by up to `distortion`, then rotated, scaled and moved; `mirror` numbers it
/// inside out (a reflection of the nodes).
SolidMesh random_hexahedron(std::mt19937_64& rng, double distortion, bool mirror) {
  std::uniform_real_distribution<double> d(-distortion, distortion), t(-100, 100), log_scale(-2, 2);
  const Eigen::Matrix3d r = testing::random_rotation(rng);
  const double s = std::pow(10.0, log_scale(rng));
  const Vec3 shift(t(rng), t(rng), t(rng));
  const Vec3 cube[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  SolidMesh mesh;
  std::vector<int> nodes;
  for (int i = 0; i < 8; ++i) {
    Vec3 p = cube[i] + Vec3(d(rng), d(rng), d(rng));
    if (mirror) p.x() = -p.x();
    nodes.push_back(mesh.add_node(100 + i, s * (r * p) + shift));
  }
  mesh.add_element(7, element_type("C3D8"), nodes);
  return mesh;
}

/// Every face of the hexahedron `mesh` (element 0), as outward_quad_corners orders it: `order(quad, manual)`
/// checks its corners against the manual's, then its normal must point away from the element's centroid.
template <class Order>
void expect_faces_point_outward(const SolidMesh& mesh, int trial, const Order& order) {
  Vec3 centroid = Vec3::Zero();
  for (int n = 0; n < 8; ++n) centroid += mesh.position(n) / 8.0;
  for (int f = 1; f <= 6; ++f) {
    const auto quad = outward_quad_corners(mesh, {0, f});
    order(quad, face_corner_indices(ElementShape::kHexahedron, f));
    const Vec3& a = mesh.position(quad[0]);
    const Vec3 normal = (mesh.position(quad[1]) - a).cross(mesh.position(quad[3]) - a);
    const Vec3 face_centre =
        0.25 * (a + mesh.position(quad[1]) + mesh.position(quad[2]) + mesh.position(quad[3]));
    EXPECT_GT(normal.dot(face_centre - centroid), 0.0) << "trial " << trial << " S" << f;
  }
}

TEST(OutwardQuadCorners, CalculixNumberingReversedPointsOutOfEveryFace) {
  std::mt19937_64 rng(41);
  for (int trial = 0; trial < 200; ++trial) {
    expect_faces_point_outward(random_hexahedron(rng, 0.2, false), trial,
                               [](const auto& quad, const auto& manual) {
                                 // A is the manual's first corner, then the manual's order reversed.
                                 EXPECT_EQ(quad[0], manual[0]);
                                 EXPECT_EQ(quad[1], manual[3]);
                                 EXPECT_EQ(quad[2], manual[2]);
                                 EXPECT_EQ(quad[3], manual[1]);
                               });
  }
}

TEST(OutwardQuadCorners, InsideOutElementIsOrientedByItsCentroid) {
  std::mt19937_64 rng(43);
  for (int trial = 0; trial < 50; ++trial) {
    expect_faces_point_outward(random_hexahedron(rng, 0.1, true), trial,
                               [](const auto& quad, const auto& manual) {
                                 EXPECT_EQ(quad[1], manual[1]);  // the manual's own order
                               });
  }
}

TEST(OutwardQuadCorners, Calculix20NodeFaceUsesTheCornerNodes) {
  SolidMesh mesh;
  const Vec3 cube[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::vector<int> nodes;
  for (int i = 0; i < 8; ++i) nodes.push_back(mesh.add_node(i + 1, cube[i]));
  for (int i = 8; i < 20; ++i)
    nodes.push_back(mesh.add_node(i + 1, Vec3(0.5, 0.5, 0.5)));  // mid-side: unused
  mesh.add_element(1, element_type("C3D20R"), nodes);
  // S2 is the top (5-8-7-6); outward is +z: 5, 6, 7, 8 seen from above counter-clockwise.
  const auto quad = outward_quad_corners(mesh, {0, 2});
  EXPECT_EQ(quad, (std::array<int, 4>{4, 5, 6, 7}));
}

/// Two unit cubes side by side along x (nodes 1..12), one C3D8 and one C3D6 pair, and a C3D4.
SolidMesh two_cubes_and_friends() {
  SolidMesh mesh;
  int id = 1;
  for (int z = 0; z <= 1; ++z) {
    for (int y = 0; y <= 1; ++y) {
      for (int x = 0; x <= 2; ++x) mesh.add_node(id++, Vec3(x, y, z));
    }
  }
  // index of (x, y, z) is x + 3 y + 6 z
  const auto n = [](int x, int y, int z) { return x + 3 * y + 6 * z; };
  mesh.add_element(10, element_type("C3D8"),
                   std::vector<int>{n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 1, 0), n(0, 0, 1), n(1, 0, 1),
                                    n(1, 1, 1), n(0, 1, 1)});
  mesh.add_element(11, element_type("C3D8R"),
                   std::vector<int>{n(1, 0, 0), n(2, 0, 0), n(2, 1, 0), n(1, 1, 0), n(1, 0, 1), n(2, 0, 1),
                                    n(2, 1, 1), n(1, 1, 1)});
  mesh.add_element(12, element_type("C3D6"),
                   std::vector<int>{n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 0, 1), n(1, 0, 1), n(1, 1, 1)});
  mesh.add_element(13, element_type("C3D4"),
                   std::vector<int>{n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 0, 1)});
  // A hexahedron collapsed into a wedge by repeating a node: its face S1 has three distinct corners.
  mesh.add_element(14, element_type("C3D8"),
                   std::vector<int>{n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(1, 1, 0), n(0, 0, 1), n(1, 0, 1),
                                    n(1, 1, 1), n(1, 1, 1)});
  return mesh;
}

TEST(SurfaceMesh, TopFacesOfTwoCubesShareAnEdgeAndPointUp) {
  const SolidMesh mesh = two_cubes_and_friends();
  const std::vector<ElementFace> faces = {{0, 2}, {1, 2}, {0, 2}, {2, 2}, {2, 3}, {3, 1}, {4, 1}};
  const SurfaceMesh s = build_surface_mesh(mesh, faces);
  ASSERT_EQ(s.segments.size(), 2u);
  EXPECT_EQ(s.repeated_faces, 1);
  EXPECT_EQ(s.skipped_faces.at("C3D6 triangle"), 1);
  EXPECT_EQ(s.skipped_faces.at("C3D6 quadrilateral"), 1);
  EXPECT_EQ(s.skipped_faces.at("C3D4 triangle"), 1);
  // The collapsed hexahedron's bottom (corners 1, 2, 5, 5) is the triangle it is, not a segment.
  EXPECT_EQ(s.skipped_faces.at("C3D8 face collapsed to a triangle"), 1);
  EXPECT_EQ(s.inside_out_faces, 0);
  // The six top nodes (ids 7..12 are the z = 1 layer) and the bottom nodes of the wedge's side, the
  // tetrahedron's base and the collapsed bottom (ids 1, 2, 5), faces of the surface search (SPEC 9), in
  // increasing id.
  EXPECT_EQ(s.node_ids, (std::vector<long>{1, 2, 5, 7, 8, 9, 10, 11, 12}));
  // The extra faces, outward: the wedge's top triangle (+z), its side y = 0 (-y), the tetrahedron's base
  // (-z), the collapsed bottom (-z).
  ASSERT_EQ(s.extra_faces.size(), 4u);
  EXPECT_EQ(s.face_count(), 6);
  const std::array<Vec3, 4> outward = {Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(0, 0, -1), Vec3(0, 0, -1)};
  for (int f = 2; f < 6; ++f) {
    const auto c = s.face_corners(f);
    EXPECT_EQ(c.size(), f == 3 ? 4u : 3u);
    const auto at = [&](int k) {
      return s.positions[static_cast<std::size_t>(c[static_cast<std::size_t>(k)])];
    };
    const Vec3 normal = (at(1) - at(0)).cross(at(static_cast<int>(c.size()) - 1) - at(0)).normalized();
    EXPECT_LT((normal - outward[static_cast<std::size_t>(f - 2)]).norm(), 1e-12) << "face " << f;
    EXPECT_EQ(s.face_element_id(f), f == 5 ? 14 : f == 4 ? 13 : 12);
  }
  for (std::size_t i = 0; i < s.segments.size(); ++i) {
    const auto& q = s.segments[i];
    const Vec3 normal =
        (s.positions[static_cast<std::size_t>(q[1])] - s.positions[static_cast<std::size_t>(q[0])])
            .cross(s.positions[static_cast<std::size_t>(q[3])] - s.positions[static_cast<std::size_t>(q[0])]);
    EXPECT_GT(normal.z(), 0.0) << i;
  }
  // Adjacency: the shared edge's nodes (x = 1: ids 8 and 11) touch both segments, the others one.
  for (int node = 0; node < s.node_count(); ++node) {
    const auto segs = s.segments_of(node);
    const long id = s.node_ids[static_cast<std::size_t>(node)];
    const bool shared = id == 8 || id == 11;
    EXPECT_EQ(segs.size(), id < 7 ? 0u : shared ? 2u : 1u) << id;
    for (int seg : segs) {
      const auto& q = s.segments[static_cast<std::size_t>(seg)];
      EXPECT_NE(std::find(q.begin(), q.end(), node), q.end());
    }
    EXPECT_TRUE(std::is_sorted(segs.begin(), segs.end()));
  }
}

TEST(SurfaceMesh, FaceNumberOutsideTheElementsTableIsRejected) {
  const SolidMesh mesh = two_cubes_and_friends();
  const std::vector<ElementFace> faces = {{0, 7}};
  EXPECT_THROW((void)build_surface_mesh(mesh, faces), InvalidArgument);
}

using contactnn::testing::grid_surface;

TEST(NodeNormals, AgreeWithGeometryNodeNormalOnABumpyMesh) {
  // An independent implementation: geometry::node_normal scans every segment for the node.
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> jiggle(-0.2, 0.2);
  const SurfaceMesh s = grid_surface(6, 5, [&](double i, double j) {
    return Vec3(i + jiggle(rng), j + jiggle(rng), 0.3 * std::sin(i) * std::cos(0.7 * j) + jiggle(rng));
  });
  const std::vector<Vec3> normals = node_normals(s);
  for (int node = 0; node < s.node_count(); ++node) {
    const Vec3 expected = geometry::node_normal(s.positions, s.segments, node);
    EXPECT_LT((normals[static_cast<std::size_t>(node)] - expected).norm(), kNormalTol) << node;
  }
}

TEST(NodeNormals, RegularCylinderGridGivesTheRadialDirection) {
  // Known answer: on a regular grid of a cylinder about the y axis, the corner normals at an interior
  // node are symmetric about the radial direction, so Eq 26 gives it exactly (up to rounding).
  const double radius = 2.0;
  const double dphi = 0.15;
  const SurfaceMesh s = grid_surface(8, 4, [&](double i, double j) {
    const double phi = (i - 4) * dphi;
    return Vec3(radius * std::sin(phi), 0.4 * j, radius * std::cos(phi));
  });
  const std::vector<Vec3> normals = node_normals(s);
  for (int j = 1; j < 4; ++j) {
    for (int i = 1; i < 8; ++i) {
      const std::size_t node = static_cast<std::size_t>(i + 9 * j);
      const Vec3 radial(s.positions[node].x() / radius, 0.0, s.positions[node].z() / radius);
      EXPECT_LT((normals[node] - radial).norm(), kNormalTol) << i << "," << j;
    }
  }
}

TEST(NodeNormals, CollapsedCornerAddsNothingAndALoneCollapsedNodeGetsZero) {
  SurfaceMesh s = grid_surface(1, 1, [](double i, double j) { return Vec3(i, j, 0); });
  // Move node 3 (i = 1, j = 1) onto the line through its neighbours 1 and 2: its corner is straight.
  s.positions[3] = Vec3(1, 0, 0) + 0.5 * (Vec3(0, 1, 0) - Vec3(1, 0, 0));
  const std::vector<Vec3> normals = node_normals(s);
  EXPECT_EQ(normals[3], Vec3::Zero());
  EXPECT_LT((normals[0] - Vec3::UnitZ()).norm(), kNormalTol);
}

/// A unit hexahedron (C3D8 or, with `quadratic`, C3D20 with its mid-side nodes at the edges' midpoints) whose
/// node `moved` (1-based) is put at `to`; nodes added in id order 1..8 (..20).
SolidMesh moved_hexahedron(bool quadratic, int moved, const Vec3& to, std::span<const int> repeat = {}) {
  SolidMesh mesh;
  const std::array<Vec3, 8> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                 Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
  static constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                        {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  std::vector<Vec3> all(x.begin(), x.end());
  if (quadratic) {
    for (const auto& e : kEdges)
      all.push_back(0.5 * (x[static_cast<std::size_t>(e[0])] + x[static_cast<std::size_t>(e[1])]));
  }
  all[static_cast<std::size_t>(moved - 1)] = to;
  std::vector<int> nodes;
  for (std::size_t i = 0; i < all.size(); ++i)
    nodes.push_back(mesh.add_node(static_cast<long>(i) + 1, all[i]));
  for (std::size_t i = 0; i + 1 < repeat.size(); i += 2) {
    nodes[static_cast<std::size_t>(repeat[i] - 1)] = nodes[static_cast<std::size_t>(repeat[i + 1] - 1)];
  }
  mesh.add_element(1, element_type(quadratic ? "C3D20" : "C3D8"), nodes);
  return mesh;
}

TEST(CollapsedFaces, CoincidenceIsWithinABillionthOfTheElementNotBeyond) {
  const std::vector<ElementFace> bottom = {{0, 1}};
  // Node 4 1e-10 of the element's size (1, its largest coordinate difference) from node 3: one point; the
  // bottom is a triangle.
  const SurfaceMesh near = build_surface_mesh(moved_hexahedron(false, 4, Vec3(1, 1 - 1e-10, 0)), bottom);
  EXPECT_EQ(near.segments.size(), 0u);
  ASSERT_EQ(near.extra_faces.size(), 1u);
  EXPECT_EQ(near.face_type(0), FaceType::kTri3);
  EXPECT_EQ(near.skipped_faces.at("C3D8 face collapsed to a triangle"), 1);
  EXPECT_EQ(near.node_ids, (std::vector<long>{1, 2, 3}));
  ASSERT_EQ(near.merged_nodes.size(), 1u);
  EXPECT_EQ(near.merged_nodes[0], (std::array<int, 2>{3, 2}));
  // The same at any scale: nothing is squared.
  for (const double scale : {1e-200, 1e200}) {
    const SolidMesh unit = moved_hexahedron(false, 4, Vec3(1, 1 - 1e-10, 0));
    SolidMesh scaled;
    for (int i = 0; i < unit.node_count(); ++i) scaled.add_node(unit.node_id(i), scale * unit.position(i));
    const auto nodes = unit.element_nodes(0);
    scaled.add_element(1, element_type("C3D8"), std::vector<int>(nodes.begin(), nodes.end()));
    const SurfaceMesh s = build_surface_mesh(scaled, bottom);
    EXPECT_EQ(s.skipped_faces, near.skipped_faces) << scale;
    EXPECT_EQ(s.face_count(), 1) << scale;
  }
  // 1e-8 of it: a thin quadrilateral, a segment of its own.
  const SurfaceMesh far = build_surface_mesh(moved_hexahedron(false, 4, Vec3(1, 1 - 1e-8, 0)), bottom);
  EXPECT_EQ(far.segments.size(), 1u);
  EXPECT_TRUE(far.skipped_faces.empty());
  EXPECT_TRUE(far.merged_nodes.empty());
}

TEST(CollapsedFaces, AFoldedFaceAndAQuad8WithoutASixNodeTriangleAreNamed) {
  // Node 3 on node 1: the bottom's diagonal collapses, the face folds onto itself (no triangle).
  const SurfaceMesh folded =
      build_surface_mesh(moved_hexahedron(false, 3, Vec3(0, 0, 0)), std::vector<ElementFace>{{0, 1}});
  EXPECT_EQ(folded.face_count(), 0);
  EXPECT_EQ(folded.skipped_faces.at("C3D8 face collapsed, not a triangle"), 1);
  // A C3D20 with corner 2 on corner 1 but its mid-side node 9 left at the old edge's midpoint: the edge 1-2
  // is a loop, the face no 6-node triangle; the flat triangle of its corners.
  const SurfaceMesh loop =
      build_surface_mesh(moved_hexahedron(true, 2, Vec3(0, 0, 0)), std::vector<ElementFace>{{0, 1}});
  ASSERT_EQ(loop.face_count(), 1);
  EXPECT_EQ(loop.face_type(0), FaceType::kTri3);
  EXPECT_EQ(loop.skipped_faces.at("C3D20 face collapsed to a flat triangle"), 1);
  // With node 9 on corner 1 too (the edge collapsed to a point), and by repeated ids: 6-node triangles.
  SolidMesh proper = moved_hexahedron(true, 2, Vec3(0, 0, 0));
  proper.set_position(8, Vec3(0, 0, 0));  // a moved node: the deck's coordinates decide, not this
  EXPECT_EQ(build_surface_mesh(proper, std::vector<ElementFace>{{0, 1}}).face_type(0), FaceType::kTri3);
  const std::array<int, 4> repeated_ids = {2, 1, 9, 1};
  const SurfaceMesh repeated = build_surface_mesh(moved_hexahedron(true, 2, Vec3(0, 0, 0), repeated_ids),
                                                  std::vector<ElementFace>{{0, 1}});
  ASSERT_EQ(repeated.face_count(), 1);
  EXPECT_EQ(repeated.face_type(0), FaceType::kTri6);
  const FaceNodes n = repeated.face_nodes(0);
  std::vector<long> ids;
  for (int i : n) ids.push_back(repeated.node_ids[static_cast<std::size_t>(i)]);
  // Outward (-z): corners 1, 4, 3, then the mid-side nodes of 1-4, 4-3, 3-1 (2-3's node 10).
  EXPECT_EQ(ids, (std::vector<long>{1, 4, 3, 12, 11, 10}));
}

TEST(CollapsedFaces, SlaveNodesKeepTheNodesMergedIntoAnotherAndTheMastersAreLeftOut) {
  // A wedge as a C3D8 (node 4 on node 3, 8 on 7): its top as the slave surface, its bottom as the master.
  ContactModel model;
  const SolidMesh wedge = moved_hexahedron(false, 4, Vec3(1, 1, 0));
  for (int n = 0; n < wedge.node_count(); ++n)
    model.mesh.add_node(n + 1, n == 7 ? Vec3(1, 1, 1) : wedge.position(n));
  model.mesh.add_element(1, element_type("C3D8"), std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7});
  model.surfaces = {{"SLAVE", SurfaceType::kElement, "ELEMENT", {{0, 2}}, {}, "here"},
                    {"MASTER", SurfaceType::kElement, "ELEMENT", {{0, 1}}, {}, "here"},
                    {"NODES", SurfaceType::kNode, "NODE", {}, {2, 3, 6, 7}, "here"}};
  model.pairs = {{"SLAVE", "MASTER", 0, 1, true, "here"}, {"NODES", "MASTER", 2, 1, true, "here"}};
  const SurfaceMesh master = master_surface(model, 0);
  EXPECT_EQ(master.node_ids, (std::vector<long>{1, 2, 3}));
  const SlaveNodes slaves = slave_nodes(model, 0, master);
  std::vector<long> ids;
  for (int n : slaves.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{5, 6, 7, 8}));  // 8 merged into 7 on the slave's triangle: still a slave
  EXPECT_EQ(slaves.midside, (std::vector<std::uint8_t>{0, 0, 0, 0}));
  // Node 4, merged into the master's node 3, is a master node.
  const SlaveNodes listed = slave_nodes(model, 1, master);
  ids.clear();
  for (int n : listed.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{7, 8}));
  EXPECT_EQ(listed.shared_with_master, 2);
}

}  // namespace
}  // namespace contactnn::mesh
