// Property test (issue 39): random masters mixing every face type -- quad4 (C3D8), quad8 (C3D20), tri3
// (C3D6), tri6 (C3D15), and triangles of hexahedra collapsed into wedges by repeated node ids or by distinct
// ids on one point (C3D8: tri3, C3D20: tri6), with the faces those collapse to a line among the master's
// faces -- on a random curved body, randomly rotated, scaled and shifted; random slave nodes above, below and
// beside the surface. Every slave node's point from contact::surface_search must be the closest point of the
// true surface, found here by brute force over the faces (true_surface_oracle.hpp: shape functions written
// there, dense sampling and a compass search), which never sees lib/mesh's collapse rules: the generator
// knows what each element is. Seeded; the same seeds every run.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "contact/surface_search.hpp"
#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "true_surface_oracle.hpp"

namespace contactnn::contact {
namespace {

using testing::TrueFace;

constexpr int kSeeds = 12;
constexpr int kSlavesPerSeed = 160;
// Relative to the cell size: the search's points are exact to rounding, the oracle's to its compass search's
// last step (1e-14 in parameters).
constexpr double kDistanceTol = 1e-9;

enum class CellKind {
  kQuad4,            ///< one C3D8
  kQuad8,            ///< one C3D20
  kTri3,             ///< two C3D6
  kTri6,             ///< two C3D15
  kQuad4Repeated,    ///< two C3D8 wedges by a repeated node id on the top and bottom
  kQuad4Coincident,  ///< two C3D8 wedges by a second node on a corner's point
  kQuad8Repeated,    ///< two C3D20 wedges by repeated ids (a corner and its collapsed edge's mid-side node)
  kQuad8Coincident,  ///< two C3D20 wedges by second nodes on those points
};
constexpr int kCellKinds = 8;

/// A random master: the mesh, its faces, and the true surface face by face.
struct Master {
  mesh::SolidMesh mesh;
  std::vector<mesh::ElementFace> faces;
  std::vector<TrueFace> truth;
  double cell = 1.0;                     ///< a cell's size (world units)
  std::map<std::string, int> collapsed;  ///< the generator's count of collapsed faces, by lib/mesh's kinds
};

class Generator {
 public:
  Generator(std::mt19937_64& rng, bool with_quad4) : rng_(rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    bend_x_ = 0.25 * u(rng);
    bend_y_ = 0.25 * u(rng);
    twist_ = 0.2 * u(rng);
    std::normal_distribution<double> g;
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    rotation_ = q.normalized().toRotationMatrix();
    scale_ = std::exp(2.0 * u(rng));  // 0.14 .. 7.4
    shift_ = Vec3(u(rng), u(rng), u(rng)) * 10.0 * scale_;
    m_.cell = scale_ * 1.0;
    std::uniform_int_distribution<int> kind(with_quad4 ? 0 : 1, kCellKinds - 1);
    for (int j = 0; j < kNy; ++j) {
      for (int i = 0; i < kNx; ++i) add_cell(i, j, static_cast<CellKind>(kind(rng)), rng() % 2 == 0);
    }
  }
  Master take() { return std::move(m_); }

  /// A point on or under the body's top: (u, v) in cells, w in [0, 1] depth (the doubled grid's k / 2).
  [[nodiscard]] Vec3 world(double u, double v, double w) const {
    const double z = bend_x_ * u * u / kNx + bend_y_ * v * v / kNy + twist_ * u * v / kNx - kDepth * w;
    return shift_ + scale_ * (rotation_ * Vec3(u, v, z));
  }
  /// The top's approximate outward normal (for placing slave nodes).
  [[nodiscard]] Vec3 up() const { return rotation_ * Vec3(0, 0, 1); }

  static constexpr int kNx = 5, kNy = 4;
  static constexpr double kDepth = 0.8;

 private:
  using Point = std::array<int, 3>;  // doubled grid (a, b, k): k = 0 top, 2 bottom

  /// The node at a doubled grid point; `copy` > 0: another node on the same point (a collapsed element's).
  int node(const Point& p, int copy = 0) {
    const auto key = std::make_tuple(p[0], p[1], p[2], copy);
    if (auto it = ids_.find(key); it != ids_.end()) return it->second;
    const int n = m_.mesh.add_node(next_id_, world(p[0] / 2.0, p[1] / 2.0, p[2] / 2.0));
    next_id_ += 1 + static_cast<long>(rng_() % 3);  // ids with gaps
    ids_.emplace(key, n);
    return n;
  }
  [[nodiscard]] Vec3 at(int n) const { return m_.mesh.position(n); }
  static Point mid(const Point& p, const Point& q) {
    return {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
  }
  static Point top(const Point& p) { return {p[0], p[1], 0}; }
  static Point bottom(const Point& p) { return {p[0], p[1], 2}; }

  void element(const char* type, const std::vector<int>& nodes, int top_face) {
    const int e = m_.mesh.add_element(next_element_++, mesh::element_type(type), nodes);
    m_.faces.push_back({e, top_face});
  }

  void add_cell(int i, int j, CellKind kind, bool diagonal) {
    const Point c00{2 * i, 2 * j, 0}, c10{2 * i + 2, 2 * j, 0}, c11{2 * i + 2, 2 * j + 2, 0},
        c01{2 * i, 2 * j + 2, 0};
    const std::array<Point, 4> quad = {c00, c10, c11, c01};  // counter-clockwise seen from above
    const std::array<std::array<Point, 3>, 2> triangles =
        diagonal ? std::array<std::array<Point, 3>, 2>{{{c00, c10, c11}, {c00, c11, c01}}}
                 : std::array<std::array<Point, 3>, 2>{{{c00, c10, c01}, {c10, c11, c01}}};
    switch (kind) {
      case CellKind::kQuad4: {
        std::vector<int> n;
        for (const Point& p : quad) n.push_back(node(bottom(p)));
        for (const Point& p : quad) n.push_back(node(top(p)));
        element("C3D8", n, 2);
        m_.truth.push_back(testing::true_quad4({at(n[4]), at(n[5]), at(n[6]), at(n[7])}));
        return;
      }
      case CellKind::kQuad8: {
        std::vector<int> n;
        for (const Point& p : quad) n.push_back(node(bottom(p)));
        for (const Point& p : quad) n.push_back(node(top(p)));
        for (int k = 0; k < 4; ++k) n.push_back(node(mid(bottom(quad[k]), bottom(quad[(k + 1) % 4]))));
        for (int k = 0; k < 4; ++k) n.push_back(node(mid(top(quad[k]), top(quad[(k + 1) % 4]))));
        for (int k = 0; k < 4; ++k) n.push_back(node(mid(bottom(quad[k]), top(quad[k]))));
        element("C3D20R", n, 2);
        m_.truth.push_back(testing::true_quad8(
            {at(n[4]), at(n[5]), at(n[6]), at(n[7]), at(n[12]), at(n[13]), at(n[14]), at(n[15])}));
        return;
      }
      default:
        for (const auto& t : triangles) add_wedge(t, kind);
    }
  }

  /// A wedge under triangle t (counter-clockwise from above), as the cell's kind writes it.
  void add_wedge(const std::array<Point, 3>& t, CellKind kind) {
    if (kind == CellKind::kTri3 || kind == CellKind::kTri6) {
      std::vector<int> n;
      for (const Point& p : t) n.push_back(node(bottom(p)));
      for (const Point& p : t) n.push_back(node(top(p)));
      if (kind == CellKind::kTri6) {
        for (int k = 0; k < 3; ++k) n.push_back(node(mid(bottom(t[k]), bottom(t[(k + 1) % 3]))));
        for (int k = 0; k < 3; ++k) n.push_back(node(mid(top(t[k]), top(t[(k + 1) % 3]))));
        for (int k = 0; k < 3; ++k) n.push_back(node(mid(bottom(t[k]), top(t[k]))));
        element("C3D15", n, 2);
        m_.truth.push_back(
            testing::true_tri6({at(n[3]), at(n[4]), at(n[5]), at(n[9]), at(n[10]), at(n[11])}));
      } else {
        element("C3D6", n, 2);
        m_.truth.push_back(testing::true_tri3({at(n[3]), at(n[4]), at(n[5])}));
      }
      return;
    }
    // A hexahedron whose bottom corners, round it, are t0, t0 again, t1, t2 (edge 1-2 collapsed), rotated by
    // r: the collapsed edge any of the four. Top the same. Repeated: t0's node twice; coincident: a second
    // node on t0's point (and on the collapsed edges' mid-side points).
    const bool repeated = kind == CellKind::kQuad4Repeated || kind == CellKind::kQuad8Repeated;
    const bool quadratic = kind == CellKind::kQuad8Repeated || kind == CellKind::kQuad8Coincident;
    const int r = static_cast<int>(rng_() % 4);
    const std::array<int, 4> round = {0, 0, 1, 2};  // triangle vertex of each corner before the rotation
    const std::array<int, 4> copy = {0, 1, 0, 0};   // the second of the collapsed pair
    std::array<int, 4> vertex{}, second{};
    for (int k = 0; k < 4; ++k) {
      vertex[static_cast<std::size_t>(k)] = round[static_cast<std::size_t>((k + r) % 4)];
      second[static_cast<std::size_t>(k)] = repeated ? 0 : copy[static_cast<std::size_t>((k + r) % 4)];
    }
    const auto corner = [&](int k, bool top_side) {
      const Point& p = t[static_cast<std::size_t>(vertex[static_cast<std::size_t>(k)])];
      return node(top_side ? top(p) : bottom(p), second[static_cast<std::size_t>(k)]);
    };
    std::vector<int> n;
    for (int k = 0; k < 4; ++k) n.push_back(corner(k, false));
    for (int k = 0; k < 4; ++k) n.push_back(corner(k, true));
    // The collapsed pair's corner positions (k, k + 1) with the same vertex.
    int collapsed = 0;
    for (int k = 0; k < 4; ++k) {
      if (vertex[static_cast<std::size_t>(k)] == vertex[static_cast<std::size_t>((k + 1) % 4)]) collapsed = k;
    }
    if (quadratic) {
      // Mid-side nodes: of an edge, the midpoint of its two vertices (on the collapsed edge: the vertex, a
      // node of its own when coincident); of a vertical edge, the midpoint of its corners (the second corner
      // of the pair: a second node there, when coincident).
      const auto edge_mid = [&](int k, bool top_side) {
        const Point& p = t[static_cast<std::size_t>(vertex[static_cast<std::size_t>(k)])];
        const Point& q = t[static_cast<std::size_t>(vertex[static_cast<std::size_t>((k + 1) % 4)])];
        const Point a = top_side ? top(p) : bottom(p), b = top_side ? top(q) : bottom(q);
        if (k == collapsed) return node(a, repeated ? 0 : 2);
        return node(mid(a, b));
      };
      for (int k = 0; k < 4; ++k) n.push_back(edge_mid(k, false));
      for (int k = 0; k < 4; ++k) n.push_back(edge_mid(k, true));
      for (int k = 0; k < 4; ++k) {
        const Point& p = t[static_cast<std::size_t>(vertex[static_cast<std::size_t>(k)])];
        n.push_back(node(mid(bottom(p), top(p)), second[static_cast<std::size_t>(k)]));
      }
    }
    element(quadratic ? "C3D20" : "C3D8", n, 2);
    const std::string type = quadratic ? "C3D20" : "C3D8";
    ++m_.collapsed[type + " face collapsed to a triangle"];
    // The side face through the collapsed edge: a line, no face. Hexahedron faces S3..S6 hold the bottom
    // edges 1-2, 2-3, 3-4, 4-1.
    m_.faces.push_back({m_.mesh.element_count() - 1, 3 + collapsed});
    ++m_.collapsed[type + " face collapsed to a line"];
    const int a = node(top(t[0])), b = node(top(t[1])), c = node(top(t[2]));
    if (!quadratic) {
      m_.truth.push_back(testing::true_tri3({at(a), at(b), at(c)}));
    } else {
      m_.truth.push_back(
          testing::true_tri6({at(a), at(b), at(c), at(node(mid(top(t[0]), top(t[1])))),
                              at(node(mid(top(t[1]), top(t[2])))), at(node(mid(top(t[2]), top(t[0]))))}));
    }
  }

  std::mt19937_64& rng_;
  Master m_;
  std::map<std::tuple<int, int, int, int>, int> ids_;
  long next_id_ = 1;
  long next_element_ = 1;
  double bend_x_ = 0.0, bend_y_ = 0.0, twist_ = 0.0, scale_ = 1.0;
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();
  Vec3 shift_ = Vec3::Zero();
};

TEST(MixedFacesProperty, EverySlaveGetsTheClosestPointOfTheTrueSurface) {
  int checked = 0, on_collapsed = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    std::mt19937_64 rng(0x39c0117a5eULL + static_cast<std::uint64_t>(seed));
    // Odd seeds: no C3D8 cell, so that the true surface is the same under --surface gregory (which smooths
    // the quad4 segments only) and both surfaces are checked.
    const bool with_quad4 = seed % 2 == 0;
    Generator g(rng, with_quad4);
    Master m = g.take();
    const mesh::SurfaceMesh master = mesh::build_surface_mesh(m.mesh, m.faces);
    SCOPED_TRACE("seed " + std::to_string(seed));
    // Every face the generator collapsed is counted as what it is; the top faces are the true surface's.
    std::map<std::string, int> collapsed;
    for (const auto& [kind, count] : master.skipped_faces) {
      if (kind.find("collapsed") != std::string::npos) collapsed[kind] = count;
    }
    EXPECT_EQ(collapsed, m.collapsed);
    EXPECT_EQ(master.face_count(), static_cast<int>(m.truth.size()));
    const std::vector<Vec3> normals = mesh::node_normals(master);

    std::uniform_real_distribution<double> across_u(-0.3, Generator::kNx + 0.3),
        across_v(-0.3, Generator::kNy + 0.3), height(-0.35, 0.35);
    std::vector<long> ids;
    std::vector<Vec3> slaves;
    for (int i = 0; i < kSlavesPerSeed; ++i) {
      const double u = across_u(rng), v = across_v(rng);
      ids.push_back(100000 + i);
      slaves.push_back(g.world(u, v, 0.0) + height(rng) * m.cell * g.up());
    }
    for (const SurfaceKind surface : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
      if (surface == SurfaceKind::kGregory && with_quad4) continue;
      SearchOptions options;
      options.surface = surface;
      options.capture_distance = 100.0 * m.cell;  // every slave node has a point
      const std::vector<NodeSegmentPair> pairs = surface_search(master, normals, ids, slaves, options);
      int wrong = 0;
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const testing::OraclePoint expected = testing::closest_point_on_true_surface(m.truth, slaves[i]);
        const NodeSegmentPair& p = pairs[i];
        ASSERT_EQ(p.status, PairStatus::kFound);
        const double distance = (slaves[i] - p.point).norm();
        const double off_surface = testing::closest_point_on_true_surface(m.truth, p.point).distance;
        ++checked;
        const mesh::ElementFace& face = master.face_of(p.segment);
        if (m.mesh.element_type(face.element).shape == mesh::ElementShape::kHexahedron &&
            master.face_type(p.segment) != mesh::FaceType::kQuad4 &&
            master.face_type(p.segment) != mesh::FaceType::kQuad8) {
          ++on_collapsed;
        }
        if (std::abs(distance - expected.distance) > kDistanceTol * m.cell ||
            off_surface > kDistanceTol * m.cell) {
          if (++wrong <= 5) {
            ADD_FAILURE() << to_string(surface) << ", slave " << i << " at (" << slaves[i].transpose()
                          << "): point (" << p.point.transpose() << ") on a "
                          << mesh::to_string(master.face_type(p.segment)) << " face at " << distance << ", "
                          << off_surface << " off the true surface; the true closest point ("
                          << expected.point.transpose() << ") at " << expected.distance;
          }
        }
      }
      EXPECT_EQ(wrong, 0) << to_string(surface) << ": of " << pairs.size() << " slave nodes";
    }
  }
  // The collapsed faces were tried: many slave nodes got their point on one.
  EXPECT_GT(on_collapsed, checked / 10) << on_collapsed << " of " << checked;
  std::printf("%d answers checked, %d on collapsed faces\n", checked, on_collapsed);
}

}  // namespace
}  // namespace contactnn::contact
