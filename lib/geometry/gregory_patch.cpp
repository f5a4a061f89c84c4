#include "geometry/gregory_patch.hpp"

#include <Eigen/Geometry>

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"

namespace contactnn::geometry {

namespace {

/// SPEC 3 edge point E(X->Y) = X + (1/3)(I - n_X n_X^T)(Y - X): the third point of the edge's cubic
/// lies in X's tangent plane, which makes the patch normal at X equal to n_X.
Vec3 edge_point(const Vec3& x, const Vec3& n_x, const Vec3& y) {
  const Vec3 chord = y - x;
  return x + (chord - n_x.dot(chord) * n_x) / 3.0;
}

struct InteriorPair {
  Vec3 near_x, near_y;
};

/// Chiyokura-Kimura interior points of the edge walked counter-clockwise from X to Y, with X' and Y'
/// the other neighbours of X and Y (SPEC 3). The cross-boundary tangent along the edge is made
/// b(t) = k(t) a(t) + h(t) c(t), with k, h linear in t, a(t) linear between the edge's binormals a0, a3
/// and c(t) the edge's own tangent; b(t) then depends only on the edge's two nodes and normals, so the
/// patch on the other side of the edge shares the tangent plane span(a(t), c(t)) (G1). b1, b2 are the
/// inner Bezier coefficients of that cubic. The edge points are the boundary's (computed once for the
/// patch): y1 = E(X->Y), y2 = E(Y->X), x_side = E(X->X'), y_side = E(Y->Y').
InteriorPair interior_points(const Vec3& x, const Vec3& n_x, const Vec3& y, const Vec3& n_y, const Vec3& y1,
                             const Vec3& y2, const Vec3& x_side, const Vec3& y_side) {
  const Vec3 c0 = y1 - x, c1 = y2 - y1, c2 = y - y2;
  const Vec3 b0 = x_side - x;
  const Vec3 b3 = y_side - y;
  const Vec3 a0 = n_x.cross(y - x).normalized();
  const Vec3 a3 = n_y.cross(y - x).normalized();
  // a0 and c0 are an orthogonal basis of X's tangent plane, which holds b0: b0 = k0 a0 + h0 c0 exactly.
  const double k0 = a0.dot(b0), h0 = c0.dot(b0) / c0.dot(c0);
  const double k1 = a3.dot(b3), h1 = c2.dot(b3) / c2.dot(c2);
  const Vec3 b1 = ((k0 + k1) * a0 + k0 * a3 + 2.0 * h0 * c1 + h1 * c0) / 3.0;
  const Vec3 b2 = ((k0 + k1) * a3 + k1 * a0 + 2.0 * h1 * c1 + h0 * c2) / 3.0;
  return InteriorPair{y1 + b1, y2 + b2};
}

const char* defect_name(GregoryDefect defect) {
  switch (defect) {
    case GregoryDefect::kNone: return "none";
    case GregoryDefect::kNonFinite: return "a non-finite node or normal component";
    case GregoryDefect::kZeroNormal: return "a node normal of zero length";
    case GregoryDefect::kDegenerateEdge: return "an edge of zero length or a node normal parallel to an edge";
  }
  return "unknown";
}

}  // namespace

GregoryDefect GregoryPatch::diagnose(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals,
                                     std::array<Vec3, 4>* unit_normals) {
  for (int i = 0; i < 4; ++i) {
    if (!nodes[i].allFinite() || !normals[i].allFinite()) return GregoryDefect::kNonFinite;
  }
  std::array<Vec3, 4> unit{};
  for (int i = 0; i < 4; ++i) {
    // A finite normal of any positive length, however large or small, is accepted (stableNormalized scales
    // by the largest component first): zero length is all components zero.
    if ((normals[i].array() == 0.0).all()) return GregoryDefect::kZeroNormal;
    unit[i] = normals[i].stableNormalized();
  }
  const double min_projected = kMinProjectedEdgeRatio * max_node_distance(nodes);
  for (int i = 0; i < 4; ++i) {
    for (const int neighbour : {(i + 1) % 4, (i + 3) % 4}) {
      const Vec3 chord = nodes[neighbour] - nodes[i];
      const Vec3 projected = chord - unit[i].dot(chord) * unit[i];
      if (!(projected.norm() > min_projected)) return GregoryDefect::kDegenerateEdge;
    }
  }
  if (unit_normals != nullptr) *unit_normals = unit;
  return GregoryDefect::kNone;
}

GregoryPatch::GregoryPatch(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals)
    : GregoryPatch(nodes, normals, (check(nodes, normals), Diagnosed{})) {}

void GregoryPatch::check(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals) {
  const GregoryDefect defect = diagnose(nodes, normals);
  CONTACTNN_REQUIRE(defect == GregoryDefect::kNone,
                    "GregoryPatch: the nodes and node normals define no patch: " << defect_name(defect));
}

GregoryPatch::GregoryPatch(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals, Diagnosed)
    : nodes_(nodes) {
  for (int i = 0; i < 4; ++i) normals_[i] = normals[i].stableNormalized();
  characteristic_length_ = max_node_distance(nodes_);

  control_ = control_points_of(nodes_, normals_);

  std::array<Vec3, 16> base;
  for (int k = 0; k < 16; ++k) base[k] = control_[k];
  for (int k = 0; k < 4; ++k) {
    const int i = 1 + (k & 1), j = 1 + (k >> 1);
    base[control_index(i, j)] = control_[interior_index(i, j, 1)];
    delta_[k] = control_[interior_index(i, j, 0)] - control_[interior_index(i, j, 1)];
  }
  // The bicubic in powers: B_i(t) = sum_a kPower[i][a] t^a, so power_[a + 4 b] = sum_ij kPower[i][a]
  // kPower[j][b] base[i + 4 j].
  static constexpr double kPower[4][4] = {
      {1.0, -3.0, 3.0, -1.0}, {0.0, 3.0, -6.0, 3.0}, {0.0, 0.0, 3.0, -3.0}, {0.0, 0.0, 0.0, 1.0}};
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      Vec3 sum = Vec3::Zero();
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          if (kPower[i][a] != 0.0 && kPower[j][b] != 0.0)
            sum += (kPower[i][a] * kPower[j][b]) * base[i + 4 * j];
        }
      }
      power_[static_cast<std::size_t>(a + 4 * b)] = sum;
    }
  }
}

std::array<Vec3, 20> GregoryPatch::control_points_of(const std::array<Vec3, 4>& nodes,
                                                     const std::array<Vec3, 4>& unit_normals) {
  std::array<Vec3, 20> control;
  const Vec3 &a = nodes[0], &b = nodes[1], &c = nodes[2], &d = nodes[3];
  const Vec3 &na = unit_normals[0], &nb = unit_normals[1], &nc = unit_normals[2], &nd = unit_normals[3];
  auto at = [&control](int i, int j) -> Vec3& { return control[control_index(i, j)]; };
  auto inner = [&control](int i, int j, int k) -> Vec3& { return control[interior_index(i, j, k)]; };

  at(0, 0) = a;
  at(3, 0) = b;
  at(3, 3) = c;
  at(0, 3) = d;
  at(1, 0) = edge_point(a, na, b);
  at(2, 0) = edge_point(b, nb, a);
  at(3, 1) = edge_point(b, nb, c);
  at(3, 2) = edge_point(c, nc, b);
  at(2, 3) = edge_point(c, nc, d);
  at(1, 3) = edge_point(d, nd, c);
  at(0, 2) = edge_point(d, nd, a);
  at(0, 1) = edge_point(a, na, d);

  // Edge X->Y, X' = node before X, Y' = node after Y (counter-clockwise); its four edge points are the
  // boundary's: E(X->Y), E(Y->X), E(X->X'), E(Y->Y').
  const InteriorPair ab = interior_points(a, na, b, nb, at(1, 0), at(2, 0), at(0, 1), at(3, 1));
  const InteriorPair bc = interior_points(b, nb, c, nc, at(3, 1), at(3, 2), at(2, 0), at(2, 3));
  const InteriorPair cd = interior_points(c, nc, d, nd, at(2, 3), at(1, 3), at(3, 2), at(0, 2));
  const InteriorPair da = interior_points(d, nd, a, na, at(0, 2), at(0, 1), at(1, 3), at(1, 0));
  inner(1, 1, 0) = ab.near_x;  // P110
  inner(2, 1, 0) = ab.near_y;  // P210
  inner(2, 1, 1) = bc.near_x;  // P211
  inner(2, 2, 1) = bc.near_y;  // P221
  inner(2, 2, 0) = cd.near_x;  // P220
  inner(1, 2, 0) = cd.near_y;  // P120
  inner(1, 2, 1) = da.near_x;  // P121
  inner(1, 1, 1) = da.near_y;  // P111
  return control;
}

}  // namespace contactnn::geometry
