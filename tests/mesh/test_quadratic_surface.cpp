// Quadratic faces in lib/mesh (SPEC 9): the mid-side nodes of C3D20, C3D15 and C3D10 faces in each face's own
// outward order, checked against CalculiX's own face tables (ifaceq, ifacew2, ifacet of gencontelem_n2f.f and
// triangucont.f, which list every face outward: corners, then the mid-side nodes of the edges corner 1-2,
// 2-3,
// ...); the surface's nodes with them; the slave nodes of both searches.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "mesh/contact_model.hpp"
#include "mesh/element_type.hpp"
#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "test_support.hpp"

namespace contactnn::mesh {
namespace {

// CalculiX's tables (1-based node numbers of the element), face by face.
const std::vector<std::vector<int>> kCalculixHex20 = {
    {4, 3, 2, 1, 11, 10, 9, 12},  {5, 6, 7, 8, 13, 14, 15, 16}, {1, 2, 6, 5, 9, 18, 13, 17},
    {2, 3, 7, 6, 10, 19, 14, 18}, {3, 4, 8, 7, 11, 20, 15, 19}, {4, 1, 5, 8, 12, 17, 16, 20}};
const std::vector<std::vector<int>> kCalculixWedge15 = {{1, 3, 2, 9, 8, 7},
                                                        {4, 5, 6, 10, 11, 12},
                                                        {1, 2, 5, 4, 7, 14, 10, 13},
                                                        {2, 3, 6, 5, 8, 15, 11, 14},
                                                        {3, 1, 4, 6, 9, 13, 12, 15}};
const std::vector<std::vector<int>> kCalculixTet10 = {
    {1, 3, 2, 7, 6, 5}, {1, 2, 4, 5, 9, 8}, {2, 3, 4, 6, 10, 9}, {1, 4, 3, 8, 10, 7}};

struct Case {
  const char* type;
  std::vector<Vec3> corners;                   // the element's corners, numbered as the manuals require
  const std::vector<std::vector<int>>* faces;  // CalculiX's face table
  int nodes;
};

std::vector<Case> cases() {
  return {
      {"C3D20R",
       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
       &kCalculixHex20,
       20},
      {"C3D15", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, &kCalculixWedge15, 15},
      {"C3D10", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, &kCalculixTet10, 10}};
}

/// One element of `c` (ids 100 + node number), corners distorted by up to 0.1 and moved rigidly; each
/// mid-side node at the midpoint of the two corners CalculiX's face table puts it between, plus up to 0.05 of
/// bulge.
SolidMesh element_of(const Case& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Matrix3d r = testing::random_rotation(rng);
  const Vec3 t(5 * u(rng), 5 * u(rng), 5 * u(rng));
  std::vector<Vec3> x(static_cast<std::size_t>(c.nodes), Vec3::Zero());
  for (std::size_t i = 0; i < c.corners.size(); ++i) x[i] = c.corners[i] + 0.1 * Vec3(u(rng), u(rng), u(rng));
  std::vector<bool> placed(x.size(), false);
  for (const auto& face : *c.faces) {
    const std::size_t k = face.size() / 2;
    for (std::size_t e = 0; e < k; ++e) {
      const auto m = static_cast<std::size_t>(face[k + e] - 1);
      if (placed[m]) continue;
      x[m] = 0.5 * (x[static_cast<std::size_t>(face[e] - 1)] +
                    x[static_cast<std::size_t>(face[(e + 1) % k] - 1)]) +
             0.05 * Vec3(u(rng), u(rng), u(rng));
      placed[m] = true;
    }
  }
  SolidMesh mesh;
  std::vector<int> nodes;
  for (std::size_t i = 0; i < x.size(); ++i)
    nodes.push_back(mesh.add_node(100 + static_cast<long>(i) + 1, r * x[i] + t));
  mesh.add_element(1, element_type(c.type), nodes);
  return mesh;
}

TEST(QuadraticFaces, FaceNodesAreCalculixsOwnFaceTables) {
  std::mt19937_64 rng(71);
  for (const Case& c : cases()) {
    for (int trial = 0; trial < 5; ++trial) {
      const SolidMesh mesh = element_of(c, rng);
      for (std::size_t f = 0; f < c.faces->size(); ++f) {
        const std::vector<int>& want = (*c.faces)[f];
        const ElementFace face{0, static_cast<int>(f) + 1};
        const SurfaceMesh surface = build_surface_mesh(mesh, std::span<const ElementFace>(&face, 1));
        ASSERT_EQ(surface.face_count(), 1) << c.type << " S" << f + 1;
        const FaceNodes got = surface.face_nodes(0);
        SCOPED_TRACE(::testing::Message() << c.type << " S" << f + 1);
        ASSERT_EQ(got.count, static_cast<int>(want.size()));
        EXPECT_EQ(got.type, want.size() == 8 ? FaceType::kQuad8 : FaceType::kTri6);
        EXPECT_TRUE(got.quadratic());
        // The same cycle as CalculiX's (which may start at another corner), mid-side nodes alongside.
        const std::size_t k = want.size() / 2;
        std::vector<long> ids;
        for (int n : got) ids.push_back(surface.node_ids[static_cast<std::size_t>(n)] - 100);
        std::size_t shift = 0;
        while (shift < k && ids[0] != want[shift]) ++shift;
        ASSERT_LT(shift, k);
        for (std::size_t i = 0; i < k; ++i) {
          EXPECT_EQ(ids[i], want[(shift + i) % k]) << "corner " << i;
          EXPECT_EQ(ids[k + i], want[k + (shift + i) % k]) << "mid-side " << i;
        }
        // The surface's nodes are all of the face's, in increasing id; face_corners the corners alone.
        EXPECT_EQ(surface.node_count(), static_cast<int>(want.size()));
        EXPECT_TRUE(std::is_sorted(surface.node_ids.begin(), surface.node_ids.end()));
        EXPECT_EQ(surface.face_corners(0).size(), k);
      }
    }
  }
}

TEST(QuadraticFaces, OnlyC3D20FacesAreSegmentsAndMidSideNodesBelongToNone) {
  // A C3D20 on a C3D8 (sharing no node), a C3D15 and a C3D10 beside them: their top faces in one surface.
  std::mt19937_64 rng(72);
  const auto all = cases();
  SolidMesh mesh;
  std::vector<ElementFace> faces;
  long id = 1;
  for (std::size_t e = 0; e < all.size(); ++e) {
    const SolidMesh one = element_of(all[e], rng);
    std::vector<int> nodes;
    for (int n = 0; n < one.node_count(); ++n)
      nodes.push_back(mesh.add_node(id++, one.position(n) + Vec3(10.0 * static_cast<double>(e), 0, 0)));
    mesh.add_element(static_cast<long>(e) + 1, element_type(all[e].type), nodes);
    faces.push_back({static_cast<int>(e), 1});
  }
  std::vector<int> linear;
  for (int i = 0; i < 8; ++i)
    linear.push_back(mesh.add_node(id++, all[0].corners[static_cast<std::size_t>(i)] + Vec3(0, 10, 0)));
  mesh.add_element(4, element_type("C3D8"), linear);
  faces.push_back({3, 2});
  const SurfaceMesh surface = build_surface_mesh(mesh, faces);
  // Segments: the C3D20's and the C3D8's faces, in the order of `faces`; extra faces: the C3D15's and
  // C3D10's.
  ASSERT_EQ(surface.segments.size(), 2u);
  ASSERT_EQ(surface.extra_faces.size(), 2u);
  EXPECT_EQ(surface.face_type(0), FaceType::kQuad8);
  EXPECT_EQ(surface.face_type(1), FaceType::kQuad4);
  EXPECT_EQ(surface.face_type(2), FaceType::kTri6);
  EXPECT_EQ(surface.face_type(3), FaceType::kTri6);
  EXPECT_EQ(surface.face_nodes(1).count, 4);
  EXPECT_EQ(surface.segment_midsides.size(), 2u);
  EXPECT_EQ(surface.segment_midsides[1], (std::array<int, 4>{-1, -1, -1, -1}));
  EXPECT_TRUE(surface.midsides_consistent());
  EXPECT_EQ(surface.skipped_faces.at("C3D15 triangle"), 1);
  EXPECT_EQ(surface.skipped_faces.at("C3D10 triangle"), 1);
  // Every node of every face, and nothing else.
  std::set<int> expected;
  for (int f = 0; f < surface.face_count(); ++f) {
    for (int n : surface.face_nodes(f)) expected.insert(surface.mesh_nodes[static_cast<std::size_t>(n)]);
  }
  EXPECT_EQ(expected.size(), surface.mesh_nodes.size());
  EXPECT_EQ(surface.node_count(), 8 + 4 + 6 + 6);
  // Mid-side nodes are in no segment (the nearest-node search never sees them) and get no Eq 26 normal.
  const std::vector<Vec3> normals = node_normals(surface);
  const FaceNodes quad8 = surface.face_nodes(0);
  for (int i = 0; i < 8; ++i) {
    const int n = quad8[i];
    EXPECT_EQ(surface.segments_of(n).size(), i < 4 ? 1u : 0u) << i;
    EXPECT_NEAR(normals[static_cast<std::size_t>(n)].norm(), i < 4 ? 1.0 : 0.0, 1e-12) << i;
  }
}

TEST(QuadraticFaces, ALinearSurfaceHasNoMidSideLists) {
  SolidMesh mesh;
  std::vector<int> nodes;
  for (int i = 0; i < 8; ++i)
    nodes.push_back(mesh.add_node(i + 1, cases()[0].corners[static_cast<std::size_t>(i)]));
  mesh.add_element(1, element_type("C3D8R"), nodes);
  const std::vector<ElementFace> faces = {{0, 1}, {0, 2}};
  const SurfaceMesh surface = build_surface_mesh(mesh, faces);
  EXPECT_TRUE(surface.segment_midsides.empty());
  EXPECT_TRUE(surface.extra_face_midsides.empty());
  EXPECT_EQ(surface.face_type(0), FaceType::kQuad4);
  EXPECT_EQ(to_string(FaceType::kQuad8), "quad8");
  EXPECT_EQ(to_string(FaceType::kTri6), "tri6");
}

TEST(QuadraticFaces, SlaveNodesOfAQuadraticSurfaceIncludeItsMidSideNodesForTheSurfaceSearchOnly) {
  // Slave: the top (S2) of a C3D20; master: the bottom (S1) of a C3D10 above it; a node surface of 3 nodes.
  std::mt19937_64 rng(73);
  const auto all = cases();
  ContactModel model;
  const SolidMesh hex = element_of(all[0], rng);
  const SolidMesh tet = element_of(all[2], rng);
  std::vector<int> h, t;
  for (int n = 0; n < hex.node_count(); ++n) h.push_back(model.mesh.add_node(n + 1, hex.position(n)));
  for (int n = 0; n < tet.node_count(); ++n)
    t.push_back(model.mesh.add_node(n + 101, tet.position(n) + Vec3(0, 0, 3)));
  model.mesh.add_element(1, element_type("C3D20"), h);
  model.mesh.add_element(2, element_type("C3D10"), t);
  SurfaceDefinition slave{"SLAVE", SurfaceType::kElement, "ELEMENT", {{0, 2}}, {}, "here"};
  SurfaceDefinition master{"MASTER", SurfaceType::kElement, "ELEMENT", {{1, 1}}, {}, "here"};
  SurfaceDefinition nodes{"NODES", SurfaceType::kNode, "NODE", {}, {h[12], h[4], h[13]}, "here"};
  model.surfaces = {slave, master, nodes};
  model.pairs = {{"SLAVE", "MASTER", 0, 1, true, "here"}, {"NODES", "MASTER", 2, 1, true, "here"}};
  const SurfaceMesh m = master_surface(model, 0);
  EXPECT_EQ(m.face_type(0), FaceType::kTri6);
  EXPECT_EQ(m.node_count(), 6);

  const SlaveNodes slaves = slave_nodes(model, 0, m);
  // S2 of the C3D20: corners 5-8, mid-side nodes 13-16 (CalculiX's table), in increasing id.
  std::vector<long> ids;
  for (int n : slaves.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{5, 6, 7, 8, 13, 14, 15, 16}));
  EXPECT_EQ(slaves.midside, (std::vector<std::uint8_t>{0, 0, 0, 0, 1, 1, 1, 1}));
  const SlaveNodes corners = corner_slaves(slaves);
  ids.clear();
  for (int n : corners.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{5, 6, 7, 8}));
  // A node surface's nodes are all slaves of both searches.
  const SlaveNodes listed = slave_nodes(model, 1, m);
  EXPECT_EQ(listed.nodes.size(), 3u);
  EXPECT_EQ(corner_slaves(listed).nodes.size(), 3u);
}

}  // namespace
}  // namespace contactnn::mesh
