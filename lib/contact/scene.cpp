#include "contact/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>

#include "contact/surface_search.hpp"

namespace contactnn::contact {

namespace {

std::string upper_trimmed(std::string s) {
  const auto first = s.find_first_not_of(" \t");
  const auto last = s.find_last_not_of(" \t");
  s = first == std::string::npos ? std::string() : s.substr(first, last - first + 1);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

/// The cyclic symmetry model whose tie joins the pair's two surfaces, or null.
const mesh::CyclicSymmetry* cyclic_model_of(const mesh::ContactModel& model,
                                            const mesh::ContactPairDefinition& pair) {
  const std::string slave = upper_trimmed(pair.slave_name), master = upper_trimmed(pair.master_name);
  for (const mesh::CyclicSymmetry& c : model.cyclic) {
    const std::string dep = upper_trimmed(c.dependent), ind = upper_trimmed(c.independent);
    if ((slave == dep && master == ind) || (slave == ind && master == dep)) return &c;
  }
  return nullptr;
}

/// `surface` and its copies rotated by +-2 pi / N about the model's axis; `normals` likewise.
void add_neighbour_sectors(const mesh::CyclicSymmetry& c, mesh::SurfaceMesh& surface,
                           std::vector<Vec3>& normals) {
  const Vec3 a = c.axis_a;
  const Vec3 axis = (c.axis_b - c.axis_a).normalized();
  const double angle = 2.0 * std::numbers::pi / c.sectors;
  const mesh::SurfaceMesh sector = surface;
  const std::vector<Vec3> sector_normals = normals;
  const auto nodes = static_cast<int>(sector.positions.size());
  const auto segments = static_cast<int>(sector.segments.size());
  const auto links = static_cast<int>(sector.adjacency.size());
  for (const int turn : {1, -1}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(turn * angle, axis).toRotationMatrix();
    const int copy = turn == 1 ? 1 : 2;
    for (int i = 0; i < nodes; ++i) {
      const auto u = static_cast<std::size_t>(i);
      surface.mesh_nodes.push_back(sector.mesh_nodes[u]);
      surface.node_ids.push_back(sector.node_ids[u]);
      surface.positions.push_back(a + r * (sector.positions[u] - a));
      normals.push_back(r * sector_normals[u]);
    }
    for (int s = 0; s < segments; ++s) {
      std::array<int, 4> quad = sector.segments[static_cast<std::size_t>(s)];
      for (int& n : quad) n += copy * nodes;
      surface.segments.push_back(quad);
      surface.segment_faces.push_back(sector.segment_faces[static_cast<std::size_t>(s)]);
      surface.segment_element_ids.push_back(sector.segment_element_ids[static_cast<std::size_t>(s)]);
      if (!sector.segment_midsides.empty()) {
        std::array<int, 4> mid = sector.segment_midsides[static_cast<std::size_t>(s)];
        for (int& n : mid) n = n < 0 ? n : n + copy * nodes;
        surface.segment_midsides.push_back(mid);
      }
    }
    for (std::size_t f = 0; f < sector.extra_faces.size(); ++f) {
      if (!sector.extra_face_midsides.empty()) {
        std::array<int, 4> mid = sector.extra_face_midsides[f];
        for (int& n : mid) n = n < 0 ? n : n + copy * nodes;
        surface.extra_face_midsides.push_back(mid);
      }
      std::array<int, 4> face = sector.extra_faces[f];
      for (int& n : face) n = n < 0 ? n : n + copy * nodes;
      surface.extra_faces.push_back(face);
      surface.extra_face_faces.push_back(sector.extra_face_faces[f]);
      surface.extra_face_element_ids.push_back(sector.extra_face_element_ids[f]);
    }
    // adjacency_offsets has nodes + 1 entries: the copy's last entry replaces the end of the one before.
    surface.adjacency_offsets.pop_back();
    for (int i = 0; i <= nodes; ++i) {
      surface.adjacency_offsets.push_back(sector.adjacency_offsets[static_cast<std::size_t>(i)] +
                                          copy * links);
    }
    for (int s : sector.adjacency) surface.adjacency.push_back(s + copy * segments);
  }
}

}  // namespace

Scene make_scene(const mesh::ContactModel& model, int k) {
  Scene scene;
  const mesh::ContactPairDefinition& pair = mesh::contact_pair(model, k);
  scene.pair = k;
  scene.slave_name = pair.slave_name;
  scene.master_name = pair.master_name;
  scene.where = pair.where;
  scene.master = mesh::master_surface(model, k);
  scene.master_normals = mesh::node_normals(scene.master);
  scene.slaves = mesh::slave_nodes(model, k, scene.master);
  if (const mesh::CyclicSymmetry* cyclic = cyclic_model_of(model, pair)) {
    add_neighbour_sectors(*cyclic, scene.master, scene.master_normals);
    scene.cyclic_sectors = cyclic->sectors;
    scene.cyclic_where = cyclic->where;
  }
  for (int n : scene.slaves.nodes) {
    scene.slave_ids.push_back(model.mesh.node_id(n));
    scene.slave_positions.push_back(model.mesh.position(n));
  }
  return scene;
}

SceneResult search_scene(const Scene& scene, const SearchOptions& options) {
  SceneResult result;
  result.pairs = options.search == GlobalSearchKind::kSurface
                     ? surface_search(scene.master, scene.master_normals, scene.slave_ids,
                                      scene.slave_positions, options)
                     : global_search(scene.master, scene.master_normals, scene.slave_ids,
                                     scene.slave_positions, options);
  for (const NodeSegmentPair& p : result.pairs) {
    if (p.status == PairStatus::kFound) {
      ++result.found;
      ++result.label_status_counts[static_cast<std::size_t>(p.label.status)];
    } else {
      ++result.no_segment;
    }
  }
  result.statistics = shape_statistics(result.pairs, options.surface);
  return result;
}

double largest_relative_offset(const SceneResult& result) {
  double largest = 0.0;
  for (const NodeSegmentPair& p : result.pairs) {
    if (p.status != PairStatus::kFound || p.nodes[0] < 0) continue;  // no quad4 configuration
    if (p.label.status != Status::kOk && p.label.status != Status::kOutside) continue;
    double shortest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i)
      shortest = std::min(shortest, (p.config.nodes[(i + 1) % 4] - p.config.nodes[i]).norm());
    if (shortest > 0.0) largest = std::max(largest, std::abs(p.label.gap) / shortest);
  }
  return largest;
}

std::vector<int> master_faces_in_deck_order(const Scene& scene) {
  std::vector<int> order(static_cast<std::size_t>(scene.master.face_count()));
  std::iota(order.begin(), order.end(), 0);
  const auto key = [&](int f) {
    return std::pair(scene.master.face_element_id(f), scene.master.face_of(f).face);
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  return order;
}

}  // namespace contactnn::contact
