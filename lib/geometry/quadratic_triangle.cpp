#include "geometry/quadratic_triangle.hpp"

#include <algorithm>

#include "geometry/bilinear_patch.hpp"

namespace contactnn::geometry {

QuadraticTriangle::QuadraticTriangle(const std::array<Vec3, 6>& nodes) : nodes_(nodes) {
  const Vec3 &a = nodes[0], &b = nodes[1], &c = nodes[2], &ab = nodes[3], &bc = nodes[4], &ca = nodes[5];
  // The shape functions of the header expanded in monomials: N_A = 1 - 3r - 3s + 2r^2 + 4rs + 2s^2,
  // N_B = 2r^2 - r, N_C = 2s^2 - s, N_AB = 4r - 4r^2 - 4rs, N_BC = 4rs, N_CA = 4s - 4rs - 4s^2.
  c_[0] = a;
  c_[1] = -3.0 * a - b + 4.0 * ab;
  c_[2] = -3.0 * a - c + 4.0 * ca;
  c_[3] = 2.0 * a + 2.0 * b - 4.0 * ab;
  c_[4] = 4.0 * (a - ab + bc - ca);
  c_[5] = 2.0 * a + 2.0 * c - 4.0 * ca;
}

Vec3 QuadraticTriangle::position(double r, double s) const {
  return c_[0] + r * (c_[1] + r * c_[3] + s * c_[4]) + s * (c_[2] + s * c_[5]);
}

SurfacePoint QuadraticTriangle::evaluate(double r, double s) const {
  SurfacePoint p;
  p.position = position(r, s);
  p.d_s = c_[1] + (2.0 * r) * c_[3] + s * c_[4];
  p.d_t = c_[2] + r * c_[4] + (2.0 * s) * c_[5];
  p.d_ss = 2.0 * c_[3];
  p.d_st = c_[4];
  p.d_tt = 2.0 * c_[5];
  return p;
}

double QuadraticTriangle::characteristic_length() const { return max_node_distance(nodes_); }

std::array<Vec3, 6> QuadraticTriangle::bezier_control_points() const {
  const auto edge = [&](std::size_t x, std::size_t y, std::size_t m) {
    return Vec3(2.0 * nodes_[m] - 0.5 * (nodes_[x] + nodes_[y]));
  };
  return {nodes_[0], nodes_[1], nodes_[2], edge(0, 1, 3), edge(1, 2, 4), edge(2, 0, 5)};
}

}  // namespace contactnn::geometry
