#include "geometry/serendipity_quad.hpp"

#include <algorithm>

#include "geometry/bilinear_patch.hpp"

namespace contactnn::geometry {

SerendipityQuad::SerendipityQuad(const std::array<Vec3, 8>& nodes) : nodes_(nodes) {
  const Vec3 &a = nodes[0], &b = nodes[1], &c = nodes[2], &d = nodes[3];
  const Vec3 &ab = nodes[4], &bc = nodes[5], &cd = nodes[6], &da = nodes[7];
  // The shape functions of the header expanded in monomials: a corner (s, t) contributes
  // (-1 + xi^2 + eta^2 + s t xi eta + t xi^2 eta + s xi eta^2)/4, a mid-side node (0, t)
  // (1 + t eta - xi^2 - t xi^2 eta)/2 and (s, 0) (1 + s xi - eta^2 - s xi eta^2)/2.
  const Vec3 corners = a + b + c + d;
  c_[0] = -0.25 * corners + 0.5 * (ab + bc + cd + da);
  c_[1] = 0.5 * (bc - da);
  c_[2] = 0.5 * (cd - ab);
  c_[3] = 0.25 * corners - 0.5 * (ab + cd);
  c_[4] = 0.25 * (a - b + c - d);
  c_[5] = 0.25 * corners - 0.5 * (bc + da);
  c_[6] = 0.25 * (-a - b + c + d) - 0.5 * (cd - ab);
  c_[7] = 0.25 * (-a + b + c - d) - 0.5 * (bc - da);
}

Vec3 SerendipityQuad::position(double xi, double eta) const {
  return c_[0] + xi * (c_[1] + xi * c_[3] + eta * c_[4] + (xi * eta) * c_[6]) +
         eta * (c_[2] + eta * c_[5] + (xi * eta) * c_[7]);
}

SurfacePoint SerendipityQuad::evaluate(double xi, double eta) const {
  SurfacePoint p;
  p.position = position(xi, eta);
  p.d_s = c_[1] + (2.0 * xi) * c_[3] + eta * c_[4] + (2.0 * xi * eta) * c_[6] + (eta * eta) * c_[7];
  p.d_t = c_[2] + xi * c_[4] + (2.0 * eta) * c_[5] + (xi * xi) * c_[6] + (2.0 * xi * eta) * c_[7];
  p.d_ss = 2.0 * c_[3] + (2.0 * eta) * c_[6];
  p.d_st = c_[4] + (2.0 * xi) * c_[6] + (2.0 * eta) * c_[7];
  p.d_tt = 2.0 * c_[5] + (2.0 * xi) * c_[7];
  return p;
}

double SerendipityQuad::characteristic_length() const { return max_node_distance(nodes_); }

std::array<Vec3, 9> SerendipityQuad::bezier_control_points() const {
  // The biquadratic interpolant of the 9 points (xi, eta) in {-1, 0, 1}^2 is the surface itself; a quadratic
  // with values f0, fm, f1 at -1, 0, 1 has Bezier coefficients f0, 2 fm - (f0 + f1)/2, f1, applied along xi
  // and then along eta.
  const auto bezier = [](const Vec3& f0, const Vec3& fm, const Vec3& f1) {
    return std::array<Vec3, 3>{f0, Vec3(2.0 * fm - 0.5 * (f0 + f1)), f1};
  };
  const Vec3 centre = position(0.0, 0.0);
  const std::array<Vec3, 3> rows[3] = {bezier(nodes_[0], nodes_[4], nodes_[1]),
                                       bezier(nodes_[7], centre, nodes_[5]),
                                       bezier(nodes_[3], nodes_[6], nodes_[2])};
  std::array<Vec3, 9> points;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::array<Vec3, 3> column = bezier(rows[0][i], rows[1][i], rows[2][i]);
    for (std::size_t j = 0; j < 3; ++j) points[3 * j + i] = column[j];
  }
  return points;
}

}  // namespace contactnn::geometry
