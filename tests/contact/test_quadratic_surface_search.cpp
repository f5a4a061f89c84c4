// contact::surface_search on a generated quadratic mesh (SPEC 9): a curved saddle-shaped body whose top is
// made of C3D20 (quad8), C3D15 (tri6) and C3D10 (tri6) faces, against a brute force over every face written
// here, against the known side of each slave node (placed along the body's own normal), with slave nodes on
// corners and mid-side nodes (ties between faces) and beyond the surface's border.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"

namespace contactnn::contact {
namespace {

// Distances of the same closest point found twice agree to rounding (coordinates of order 1).
constexpr double kExact = 1e-12;

constexpr int kNx = 6, kNy = 4;  // cells: columns 0-1 C3D20, 2-3 C3D15 (two wedges), 4-5 C3D10 (six tets)
constexpr double kDepth = 0.8;

/// The body: (u, v, w) in [0, 1]^3 -> a saddle z = 0.15 (x^2 - y^2) on top (w = 0), kDepth below it (w = 1).
Vec3 body_point(double u, double v, double w) {
  const double x = 4.0 * u - 2.0, y = 3.0 * v - 1.5;
  return {x, y, 0.15 * (x * x - y * y) - kDepth * w};
}
/// The unit normal of the top surface, outward (up).
Vec3 top_normal(double u, double v) {
  const double x = 4.0 * u - 2.0, y = 3.0 * v - 1.5;
  return Vec3(-0.3 * x, 0.3 * y, 1.0).normalized();
}

struct Body {
  mesh::SolidMesh mesh;
  std::vector<mesh::ElementFace> top;  ///< every element's face on w = 0
};

/// The body meshed on a grid of kNx x kNy x 1 cells, nodes on the doubled grid (mid-side nodes on the curved
/// map, so that the faces are curved); each element's node order checked by its volume.
Body make_body() {
  Body b;
  std::map<std::tuple<int, int, int>, int> ids;  // doubled (a, b, k) -> node index; k = 0 top, 2 bottom
  const auto node = [&](int a, int c, int k) {
    const auto key = std::make_tuple(a, c, k);
    if (auto it = ids.find(key); it != ids.end()) return it->second;
    const int n = b.mesh.add_node(static_cast<long>(ids.size()) + 1,
                                  body_point(a / (2.0 * kNx), c / (2.0 * kNy), k / 2.0));
    ids.emplace(key, n);
    return n;
  };
  using Corner = std::array<int, 3>;  // doubled grid position
  const auto mid = [&](const Corner& p, const Corner& q) {
    return node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
  };
  const auto at = [&](const Corner& p) { return node(p[0], p[1], p[2]); };
  const auto volume = [&](const Corner& o, const Corner& x, const Corner& y, const Corner& z) {
    const Vec3 a = b.mesh.position(at(o));
    return (b.mesh.position(at(x)) - a).cross(b.mesh.position(at(y)) - a).dot(b.mesh.position(at(z)) - a);
  };
  long element = 1;
  const auto add = [&](const char* type, const std::vector<Corner>& corners,
                       const std::vector<std::array<int, 2>>& edges, int top_face) {
    std::vector<int> nodes;
    for (const Corner& c : corners) nodes.push_back(at(c));
    for (const auto& e : edges)
      nodes.push_back(mid(corners[static_cast<std::size_t>(e[0])], corners[static_cast<std::size_t>(e[1])]));
    const int index = b.mesh.add_element(element++, mesh::element_type(type), nodes);
    b.top.push_back({index, top_face});
  };
  const std::vector<std::array<int, 2>> hex_edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                                     {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const std::vector<std::array<int, 2>> wedge_edges = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                                       {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  const std::vector<std::array<int, 2>> tet_edges = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  const int tet_faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};  // S1..S4
  for (int j = 0; j < kNy; ++j) {
    for (int i = 0; i < kNx; ++i) {
      const auto c = [&](int di, int dj, int top) { return Corner{2 * (i + di), 2 * (j + dj), top ? 0 : 2}; };
      // Bottom 1-4 counter-clockwise seen from above, then the top: positive volume, top face S2 (hexahedron
      // 5-8-7-6, wedge 4-6-5).
      const std::vector<Corner> hex = {c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0),
                                       c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)};
      if (i < 2) {
        EXPECT_GT(volume(hex[0], hex[1], hex[3], hex[4]), 0.0);
        add("C3D20R", hex, hex_edges, 2);
      } else if (i < 4) {
        for (const auto& w : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
          const std::vector<Corner> wedge = {
              hex[static_cast<std::size_t>(w[0])],     hex[static_cast<std::size_t>(w[1])],
              hex[static_cast<std::size_t>(w[2])],     hex[static_cast<std::size_t>(w[0] + 4)],
              hex[static_cast<std::size_t>(w[1] + 4)], hex[static_cast<std::size_t>(w[2] + 4)]};
          add("C3D15", wedge, wedge_edges, 2);
        }
      } else {
        // Six tetrahedra along the diagonal from the bottom's first corner to the top's third (Kuhn).
        for (const auto& path :
             {std::array<int, 3>{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}) {
          Corner p = hex[0];
          std::vector<Corner> tet = {p};
          for (int axis : path) {
            p[static_cast<std::size_t>(axis)] += axis == 2 ? -2 : 2;  // k: 2 (bottom) -> 0 (top)
            tet.push_back(p);
          }
          if (volume(tet[0], tet[1], tet[2], tet[3]) < 0) std::swap(tet[1], tet[2]);
          // The face on top, if any: its three corners at k = 0.
          int top_face = 0;
          for (int f = 0; f < 4; ++f) {
            bool on_top = true;
            for (int v : tet_faces[f]) on_top = on_top && tet[static_cast<std::size_t>(v)][2] == 0;
            if (on_top) top_face = f + 1;
          }
          std::vector<int> nodes;
          for (const Corner& q : tet) nodes.push_back(at(q));
          for (const auto& e : tet_edges)
            nodes.push_back(mid(tet[static_cast<std::size_t>(e[0])], tet[static_cast<std::size_t>(e[1])]));
          const int index = b.mesh.add_element(element++, mesh::element_type("C3D10"), nodes);
          if (top_face > 0) b.top.push_back({index, top_face});
        }
      }
    }
  }
  return b;
}

struct Brute {
  int face = -1;
  double distance = std::numeric_limits<double>::infinity();
  Vec3 point = Vec3::Zero();
};

/// Every face's closest point (the per-face projections of lib/projection, themselves tested against an
/// oracle), the nearest winning, ties (1e-12) to the lower element id, then the lower face number.
Brute brute_force(const mesh::SurfaceMesh& m, const Vec3& s) {
  Brute best;
  for (int f = 0; f < m.face_count(); ++f) {
    const mesh::FaceNodes nodes = m.face_nodes(f);
    projection::FaceClosestPoint p;
    if (nodes.type == mesh::FaceType::kQuad8) {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i)
        x[static_cast<std::size_t>(i)] = m.positions[static_cast<std::size_t>(nodes[i])];
      p = projection::closest_point_on_serendipity_quad(geometry::SerendipityQuad(x), s);
    } else {
      EXPECT_EQ(nodes.type, mesh::FaceType::kTri6);
      std::array<Vec3, 6> x;
      for (int i = 0; i < 6; ++i)
        x[static_cast<std::size_t>(i)] = m.positions[static_cast<std::size_t>(nodes[i])];
      p = projection::closest_point_on_quadratic_triangle(geometry::QuadraticTriangle(x), s);
    }
    if (p.status != Status::kOk) continue;
    const auto key = [&](int g) { return std::pair(m.face_element_id(g), m.face_of(g).face); };
    if (best.face < 0 || p.distance < best.distance - kExact ||
        (p.distance <= best.distance + kExact && key(f) < key(best.face))) {
      best = {f, p.distance, p.point};
    }
  }
  return best;
}

TEST(QuadraticSurfaceSearch, EqualsABruteForceOverEveryFaceAndKnowsEachSlavesSide) {
  const Body body = make_body();
  const mesh::SurfaceMesh master = mesh::build_surface_mesh(body.mesh, body.top);
  ASSERT_EQ(master.face_count(), 2 * kNy + 2 * 2 * kNy + 2 * 2 * kNy);
  int counts[4] = {0, 0, 0, 0};
  for (int f = 0; f < master.face_count(); ++f) ++counts[static_cast<int>(master.face_type(f))];
  EXPECT_EQ(counts[static_cast<int>(mesh::FaceType::kQuad8)], 2 * kNy);
  EXPECT_EQ(counts[static_cast<int>(mesh::FaceType::kTri6)], 8 * kNy);

  // Slave nodes: along the body's own normal at random (u, v), some beyond its border; every surface node
  // (corners and mid-side nodes: distance 0 to several faces); far away ones.
  std::mt19937_64 rng(91);
  std::uniform_real_distribution<double> uv(-0.08, 1.08), magnitude(0.02, 0.3), sign(-1.0, 1.0);
  const double h = 4.0 / kNx;
  std::vector<Vec3> slaves;
  std::vector<double> side;  // +1 outside, -1 inside, 0 unknown (beyond the border or on the surface)
  for (int i = 0; i < 600; ++i) {
    const double u = uv(rng), v = uv(rng), off = (sign(rng) < 0 ? -1.0 : 1.0) * magnitude(rng) * h;
    slaves.push_back(body_point(u, v, 0.0) + off * top_normal(u, v));
    const bool within = u > 0.01 && u < 0.99 && v > 0.01 && v < 0.99;
    side.push_back(within ? (off > 0 ? 1.0 : -1.0) : 0.0);
  }
  for (const Vec3& x : master.positions) {
    slaves.push_back(x);
    side.push_back(0.0);
  }
  slaves.push_back(Vec3(0, 0, 10));
  side.push_back(0.0);
  std::vector<long> ids(slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  SearchOptions options;
  const auto pairs = surface_search(master, {}, ids, slaves, options);
  options.brute_force_faces = true;
  const auto every = surface_search(master, {}, ids, slaves, options);
  options.surface = SurfaceKind::kGregory;  // quadratic faces are their own surface under gregory too
  const auto gregory = surface_search(master, mesh::node_normals(master), ids, slaves, options);
  const double capture = capture_distance(master, SearchOptions{});

  int located[3] = {0, 0, 0};
  int sided = 0;
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "slave " << i << " at " << slaves[i].transpose());
    const Brute want = brute_force(master, slaves[i]);
    const NodeSegmentPair& got = pairs[i];
    if (want.distance > capture) {
      EXPECT_EQ(got.status, PairStatus::kNoSegment);
      continue;
    }
    ASSERT_EQ(got.status, PairStatus::kFound);
    EXPECT_EQ(got.segment, want.face);
    EXPECT_NEAR(std::abs(got.label.gap), want.distance, kExact);
    EXPECT_LE((got.point - want.point).norm(), kExact);
    EXPECT_EQ(got.label.status, Status::kOk);
    EXPECT_EQ(got.nodes[0], -1);  // not a quad4: no SPEC 7 node order
    EXPECT_EQ(got.face_param, got.label.param);
    // The tree search and the scan of every face agree to the bit; gregory changes nothing here.
    EXPECT_EQ(every[i].segment, got.segment);
    EXPECT_EQ(every[i].label.gap, got.label.gap);
    EXPECT_EQ(gregory[i].segment, got.segment);
    EXPECT_EQ(gregory[i].label.gap, got.label.gap);
    ++located[static_cast<int>(got.location)];
    if (side[i] != 0.0) {
      EXPECT_EQ(got.label.gap > 0 ? 1.0 : -1.0, side[i]) << "location " << static_cast<int>(got.location);
      ++sided;
    }
  }
  // Faces, edges and vertices all occur, and most slaves have a known side.
  EXPECT_GT(located[0], 200);
  EXPECT_GT(located[1], 30);
  EXPECT_GT(located[2], 20);
  EXPECT_GT(sided, 400);
  std::printf("locations: face %d, edge %d, vertex %d; %d slaves with a known side\n", located[0], located[1],
              located[2], sided);
}

TEST(QuadraticSurfaceSearch, TheBoundingSpheresHoldTheCurvedFaces) {
  // A quad8 whose mid-side nodes bulge far beyond its corners: a slave over the bulge is nearest to it
  // although the face's corners and nodes are farther than the capture distance's sphere around them would
  // say.
  mesh::SolidMesh mesh;
  const Vec3 corners[8] = {{0, 0, -1}, {1, 0, -1}, {1, 1, -1}, {0, 1, -1},
                           {0, 0, 0},  {1, 0, 0},  {1, 1, 0},  {0, 1, 0}};
  std::vector<int> nodes;
  for (int i = 0; i < 8; ++i) nodes.push_back(mesh.add_node(i + 1, corners[i]));
  // Mid-side nodes at their edges' midpoints, but the top edges' lifted by 0.5.
  const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                            {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (int e = 0; e < 12; ++e) {
    Vec3 m = 0.5 * (corners[edges[e][0]] + corners[edges[e][1]]);
    if (e >= 4 && e < 8) m.z() += 0.5;
    nodes.push_back(mesh.add_node(9 + e, m));
  }
  mesh.add_element(1, mesh::element_type("C3D20"), nodes);
  const std::vector<mesh::ElementFace> top = {{0, 2}};
  const mesh::SurfaceMesh master = mesh::build_surface_mesh(mesh, top);
  ASSERT_EQ(master.face_type(0), mesh::FaceType::kQuad8);
  // The face's middle: P(0, 0) = -1/4 sum(corners) + 1/2 sum(mid-sides).
  const geometry::SerendipityQuad face({corners[4], corners[5], corners[6], corners[7], Vec3(0.5, 0, 0.5),
                                        Vec3(1, 0.5, 0.5), Vec3(0.5, 1, 0.5), Vec3(0, 0.5, 0.5)});
  const double top_z = face.position(0, 0).z();
  EXPECT_NEAR(top_z, 1.0, kExact);  // -1/4 * 0 + 1/2 * 2: above every node (0.5 at most)
  SearchOptions options;
  options.capture_distance = 0.1;
  const std::vector<Vec3> slaves = {Vec3(0.5, 0.5, top_z + 0.05)};
  const std::vector<long> ids = {1};
  const auto pairs = surface_search(master, {}, ids, slaves, options);
  ASSERT_EQ(pairs[0].status, PairStatus::kFound);
  EXPECT_NEAR(pairs[0].label.gap, 0.05, 1e-9);
  EXPECT_EQ(pairs[0].location, Location::kFace);
}

TEST(QuadraticSurfaceSearch, InconsistentMidSideListsAreRefused) {
  const Body body = make_body();
  mesh::SurfaceMesh master = mesh::build_surface_mesh(body.mesh, body.top);
  master.segment_midsides.pop_back();
  const std::vector<Vec3> slaves = {Vec3(0, 0, 1)};
  const std::vector<long> ids = {1};
  EXPECT_THROW((void)surface_search(master, {}, ids, slaves, SearchOptions{}), InvalidArgument);
}

TEST(QuadraticSurfaceSearch, TheCertificateAnswersAsTheReferenceWithFewerReferenceFaces) {
  // Issue 38: the quad8 and tri6 faces' CurvedCertificate (NarrowPhase::kCertified) gives the reference's
  // answers (NarrowPhase::kReference: every face by the reference), spending the reference on far fewer
  // faces.
  const Body body = make_body();
  const mesh::SurfaceMesh master = mesh::build_surface_mesh(body.mesh, body.top);
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> uv(-0.05, 1.05), off(-0.3, 0.3);
  const double h = 4.0 / kNx;
  std::vector<Vec3> slaves;
  for (int i = 0; i < 2000; ++i) {
    const double u = uv(rng), v = uv(rng);
    slaves.push_back(body_point(u, v, 0.0) + off(rng) * h * top_normal(u, v));
  }
  std::vector<long> ids(slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  SearchOptions options;
  options.narrow = NarrowPhase::kCertified;
  const auto certified = surface_search(master, {}, ids, slaves, options);
  options.narrow = NarrowPhase::kReference;
  const auto reference = surface_search(master, {}, ids, slaves, options);
  long certified_faces = 0, reference_faces = 0;
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "slave " << i << " at " << slaves[i].transpose());
    ASSERT_EQ(certified[i].status, reference[i].status);
    certified_faces += certified[i].reference_faces;
    reference_faces += reference[i].reference_faces;
    if (reference[i].status != PairStatus::kFound) continue;
    EXPECT_EQ(certified[i].segment, reference[i].segment);
    EXPECT_EQ(certified[i].location, reference[i].location);
    EXPECT_NEAR(certified[i].label.gap, reference[i].label.gap, kExact);
    EXPECT_LE((certified[i].point - reference[i].point).norm(), kExact);
    EXPECT_NEAR(certified[i].face_param[0], reference[i].face_param[0], 1e-10);
    EXPECT_NEAR(certified[i].face_param[1], reference[i].face_param[1], 1e-10);
  }
  std::printf("reference faces: certified %ld, reference %ld (%zu slaves)\n", certified_faces,
              reference_faces, slaves.size());
  EXPECT_GT(reference_faces, static_cast<long>(slaves.size()));
  EXPECT_LT(certified_faces, reference_faces / 5);
}

}  // namespace
}  // namespace contactnn::contact
