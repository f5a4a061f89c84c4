// Random queries on the faces of FaceSearch (tri3, tri6, quad8) for its tests and benchmark: a face of unit
// size, its corners warped, its mid-side nodes off their edges' midpoints, placed at a random position,
// orientation and scale, and a slave node over a foot point inside it. The reference is the projection's
// closest point on the true face (projection::closest_point_on_serendipity_quad / _quadratic_triangle).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "projection/closest_point_on_face.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"
#include "search/face_search.hpp"

namespace contactnn::testing {

using geometry::Vec3;

/// One face (its nodes in SPEC 9's order) and a slave node.
struct FaceQuery {
  std::vector<Vec3> nodes;
  Vec3 slave;
  std::array<double, 2> foot{};  ///< the parameters S was placed over
};

struct FaceQueryOptions {
  double warp = 0.15;      ///< corners move by up to this (unit face)
  double curvature = 0.1;  ///< mid-side nodes move off their chord's midpoint by up to this x the edge length
  double height = 0.1;     ///< |S - P(foot)| along the normal up to this x the face size, either side
  double foot_inset = 0.05;  ///< the foot stays this far inside the domain (parameter units of a unit width)
  bool place = true;         ///< random position, orientation and scale (10^-3 .. 10^3)
  bool flat = false;         ///< the corners stay in one plane (the warp moves them in it)
};

/// P and the unit normal of a face at its parameters.
inline geometry::SurfacePoint face_point(search::FaceKind kind, const std::vector<Vec3>& x, double s,
                                         double t) {
  if (kind == search::FaceKind::kQuad8) {
    std::array<Vec3, 8> n;
    for (int i = 0; i < 8; ++i) n[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
    return geometry::SerendipityQuad(n).evaluate(s, t);
  }
  std::array<Vec3, 6> n;
  for (int i = 0; i < 3; ++i) n[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
  for (int e = 0; e < 3; ++e) {
    n[static_cast<std::size_t>(3 + e)] =
        kind == search::FaceKind::kTri6
            ? x[static_cast<std::size_t>(3 + e)]
            : 0.5 * (x[static_cast<std::size_t>(e)] + x[static_cast<std::size_t>((e + 1) % 3)]);
  }
  return geometry::QuadraticTriangle(n).evaluate(s, t);
}

inline FaceQuery random_face_query(search::FaceKind kind, std::mt19937_64& rng,
                                   const FaceQueryOptions& o = {}) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.0, 1.0);
  const auto jitter = [&](double r) { return Vec3(r * unit(rng), r * unit(rng), r * unit(rng)); };
  FaceQuery q;
  const bool quad = kind == search::FaceKind::kQuad8;
  const int corners = quad ? 4 : 3;
  const std::vector<Vec3> base = quad ? std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}
                                      : std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < corners; ++i) {
    Vec3 move = jitter(o.warp);
    if (o.flat) move.z() = 0.0;
    q.nodes.push_back(base[static_cast<std::size_t>(i)] + move);
  }
  if (kind != search::FaceKind::kTri3) {
    for (int e = 0; e < corners; ++e) {
      const Vec3& a = q.nodes[static_cast<std::size_t>(e)];
      const Vec3& b = q.nodes[static_cast<std::size_t>((e + 1) % corners)];
      q.nodes.push_back(0.5 * (a + b) + jitter(o.curvature * (b - a).norm()));
    }
  }
  if (o.place) {
    const Eigen::Quaterniond rotation = Eigen::Quaterniond::UnitRandom();
    const double scale = std::pow(10.0, 3.0 * unit(rng));
    const Vec3 shift = jitter(100.0 * scale);
    for (Vec3& x : q.nodes) x = rotation * x * scale + shift;
  }
  const double size = (q.nodes[1] - q.nodes[0]).norm();
  const double inset = o.foot_inset;
  double s, t;
  if (quad) {
    s = (1.0 - 2.0 * inset) * unit(rng);
    t = (1.0 - 2.0 * inset) * unit(rng);
  } else {
    do {
      s = positive(rng);
      t = positive(rng);
    } while (s < inset || t < inset || s + t > 1.0 - inset);
  }
  q.foot = {s, t};
  const geometry::SurfacePoint p = face_point(kind, q.nodes, s, t);
  const Vec3 n = p.d_s.cross(p.d_t).normalized();
  q.slave = p.position + o.height * size * unit(rng) * n;
  return q;
}

/// The raw row of FaceSearch::run: nodes, then S.
inline void append_row(const FaceQuery& q, std::vector<double>& raw) {
  for (const Vec3& x : q.nodes) raw.insert(raw.end(), {x.x(), x.y(), x.z()});
  raw.insert(raw.end(), {q.slave.x(), q.slave.y(), q.slave.z()});
}

/// The reference closest point on the true face (interior, edges and vertices).
inline projection::FaceClosestPoint reference_point(search::FaceKind kind, const FaceQuery& q) {
  if (kind == search::FaceKind::kTri3) {
    return projection::closest_point_on_triangle({q.nodes[0], q.nodes[1], q.nodes[2]}, q.slave);
  }
  if (kind == search::FaceKind::kTri6) {
    std::array<Vec3, 6> n;
    for (int i = 0; i < 6; ++i) n[static_cast<std::size_t>(i)] = q.nodes[static_cast<std::size_t>(i)];
    return projection::closest_point_on_quadratic_triangle(geometry::QuadraticTriangle(n), q.slave);
  }
  std::array<Vec3, 8> n;
  for (int i = 0; i < 8; ++i) n[static_cast<std::size_t>(i)] = q.nodes[static_cast<std::size_t>(i)];
  return projection::closest_point_on_serendipity_quad(geometry::SerendipityQuad(n), q.slave);
}

/// The node orders of a face that keep its orientation and those that reverse it (the cyclic relabellings,
/// then the mirrored ones): order[k][i] is the caller's node at position i of relabelling k. 6 for triangles,
/// 8 for quads; the mid-side nodes follow their edges.
inline std::vector<std::vector<int>> face_orders(search::FaceKind kind) {
  const int c = kind == search::FaceKind::kQuad8 ? 4 : 3;
  const bool mids = kind != search::FaceKind::kTri3;
  std::vector<std::vector<int>> orders;
  for (int mirror = 0; mirror < 2; ++mirror) {
    for (int r = 0; r < c; ++r) {
      std::vector<int> order(static_cast<std::size_t>(mids ? 2 * c : c));
      for (int j = 0; j < c; ++j) order[static_cast<std::size_t>(j)] = mirror ? (r - j + c) % c : (r + j) % c;
      if (mids) {
        for (int j = 0; j < c; ++j) {
          const int a = order[static_cast<std::size_t>(j)], b = order[static_cast<std::size_t>((j + 1) % c)];
          order[static_cast<std::size_t>(c + j)] = c + (mirror ? b : a);
        }
      }
      orders.push_back(order);
    }
  }
  return orders;
}

}  // namespace contactnn::testing
