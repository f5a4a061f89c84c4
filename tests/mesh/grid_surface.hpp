// A structured quad surface mesh for the tests of lib/mesh and lib/contact: nodes and segments of an
// nx x ny grid, counter-clockwise seen from +z, with the node-to-segment adjacency of mesh::set_adjacency
// (which tests/mesh/test_surface_mesh.cpp checks against a hand-made surface).
#pragma once

#include <functional>
#include <vector>

#include "geometry/configuration.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::testing {

/// Node (i, j) at point(i, j), index i + (nx + 1) j, id that + 1; segment (i, j) = nodes (i, j), (i+1, j),
/// (i+1, j+1), (i, j+1).
inline mesh::SurfaceMesh grid_surface(int nx, int ny,
                                      const std::function<geometry::Vec3(double, double)>& point) {
  mesh::SurfaceMesh s;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      s.node_ids.push_back(static_cast<long>(s.node_ids.size()) + 1);
      s.positions.push_back(point(i, j));
    }
  }
  const auto at = [&](int i, int j) { return i + (nx + 1) * j; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i)
      s.segments.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  }
  mesh::set_adjacency(s);
  return s;
}

/// grid_surface with the element ids and faces the surface search's tie rule reads (segment q: element q + 1,
/// face S1).
inline mesh::SurfaceMesh searched_grid_surface(int nx, int ny,
                                               const std::function<geometry::Vec3(double, double)>& point) {
  mesh::SurfaceMesh s = grid_surface(nx, ny, point);
  for (std::size_t q = 0; q < s.segments.size(); ++q) {
    s.segment_faces.push_back({static_cast<int>(q), 1});
    s.segment_element_ids.push_back(static_cast<long>(q) + 1);
  }
  return s;
}

}  // namespace contactnn::testing
