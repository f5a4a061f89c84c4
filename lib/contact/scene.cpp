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
#include "core/error.hpp"

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

/// The cyclic copies' positions and normals from the sector's (Scene::sector_nodes).
void place_copies(Scene& scene) {
  const auto nodes = static_cast<std::size_t>(scene.sector_nodes);
  const Vec3 a = scene.cyclic_origin;
  for (std::size_t copy = 1; copy <= 2; ++copy) {
    const Eigen::Matrix3d& r = scene.cyclic_rotations[copy - 1];
    for (std::size_t i = 0; i < nodes; ++i) {
      scene.master.positions[copy * nodes + i] = a + r * (scene.master.positions[i] - a);
      scene.master_normals[copy * nodes + i] = r * scene.master_normals[i];
    }
  }
}

/// The scene's master surface and its copies rotated by +-2 pi / N about the model's axis (their faces and
/// node lists; place_copies puts their nodes).
void add_neighbour_sectors(const mesh::CyclicSymmetry& c, Scene& scene) {
  mesh::SurfaceMesh& surface = scene.master;
  scene.cyclic_origin = c.axis_a;
  const Vec3 axis = (c.axis_b - c.axis_a).normalized();
  const double angle = 2.0 * std::numbers::pi / c.sectors;
  scene.cyclic_rotations = {Eigen::AngleAxisd(angle, axis).toRotationMatrix(),
                            Eigen::AngleAxisd(-angle, axis).toRotationMatrix()};
  const mesh::SurfaceMesh sector = surface;
  const auto nodes = static_cast<int>(sector.positions.size());
  const auto segments = static_cast<int>(sector.segments.size());
  const auto links = static_cast<int>(sector.adjacency.size());
  surface.positions.resize(3 * sector.positions.size());
  scene.master_normals.resize(3 * sector.positions.size());
  for (const int copy : {1, 2}) {
    for (int i = 0; i < nodes; ++i) {
      const auto u = static_cast<std::size_t>(i);
      surface.mesh_nodes.push_back(sector.mesh_nodes[u]);
      surface.node_ids.push_back(sector.node_ids[u]);
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
  scene.sector_nodes = scene.master.node_count();
  if (const mesh::CyclicSymmetry* cyclic = cyclic_model_of(model, pair)) {
    add_neighbour_sectors(*cyclic, scene);
    place_copies(scene);
    scene.cyclic_sectors = cyclic->sectors;
    scene.cyclic_where = cyclic->where;
  }
  for (int n : scene.slaves.nodes) {
    scene.slave_ids.push_back(model.mesh.node_id(n));
    scene.slave_positions.push_back(model.mesh.position(n));
  }
  return scene;
}

void move_scene(Scene& scene, std::span<const Vec3> master, std::span<const Vec3> slaves) {
  const auto nodes = static_cast<std::size_t>(scene.sector_nodes);
  CONTACTNN_REQUIRE(master.size() == nodes && slaves.size() == scene.slave_positions.size(),
                    master.size() << " master and " << slaves.size() << " slave positions for a scene of "
                                  << nodes << " and " << scene.slave_positions.size());
  std::copy(master.begin(), master.end(), scene.master.positions.begin());
  std::copy(slaves.begin(), slaves.end(), scene.slave_positions.begin());
  mesh::node_normals(scene.master, std::span<Vec3>(scene.master_normals).first(nodes));
  if (scene.cyclic_sectors > 0) place_copies(scene);
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
