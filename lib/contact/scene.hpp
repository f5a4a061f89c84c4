// A scene: one contact pair of a deck made ready for the global search, and the search's result with its
// shape statistics (what `gen-configs --scene` reports, SPEC 7).
#pragma once

#include <Eigen/Core>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "contact/global_search.hpp"
#include "contact/shape_statistics.hpp"
#include "mesh/contact_model.hpp"

namespace contactnn::contact {

struct Scene {
  int pair = 0;  ///< K, the *CONTACT PAIR data line (from 0)
  std::string slave_name, master_name;
  std::string where;  ///< "'file':line" of the pair's data line
  /// Segments oriented outward. For a pair between the two cut faces of a cyclic symmetry model: the master
  /// surface of the sector and its copies rotated one sector either way (nodes and segments in that order,
  /// node ids repeated in each copy), so that a slave node finds the neighbouring sector's face it touches.
  mesh::SurfaceMesh master;
  int cyclic_sectors = 0;            ///< N of the cyclic symmetry model applied, 0 when none
  std::string cyclic_where;          ///< its "'file':line"
  std::vector<Vec3> master_normals;  ///< unit node normals of Eq 26 (zero where a node has none)
  mesh::SlaveNodes slaves;           ///< slave nodes in increasing id, skipped slave faces
  std::vector<long> slave_ids;       ///< deck ids of slaves.nodes
  std::vector<Vec3> slave_positions;
  /// The master nodes of the pair's own surface: all of master's without cyclic symmetry, the sector's
  /// (master's first sector_nodes) with it; copy c (1: +360/N, 2: -360/N) of sector node i is master node
  /// c * sector_nodes + i, at cyclic_origin + cyclic_rotations[c - 1] * (position - cyclic_origin).
  int sector_nodes = 0;
  Vec3 cyclic_origin = Vec3::Zero();
  std::array<Eigen::Matrix3d, 2> cyclic_rotations{Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Identity()};
};

/// The scene of pair `k` of `model`: master surface, its node normals, slave nodes (SPEC 7). When the pair's
/// two surfaces are the dependent and independent surface of a *CYCLIC SYMMETRY MODEL's tie (either order),
/// the master surface is repeated in the two neighbouring sectors (Scene::master).
/// Errors of mesh::contact_pair, mesh::master_surface and mesh::slave_nodes.
[[nodiscard]] Scene make_scene(const mesh::ContactModel& model, int k);

/// Moves `scene` (make_scene's) to new node positions without building anything again: `master` the
/// positions of the sector's master nodes (scene.master's first sector_nodes, in their order), `slaves` those
/// of scene.slaves.nodes; the node normals computed again (mesh::node_normals) and the cyclic copies placed
/// again. Faces, their orientation, ids and sets stay as they are. Gives the positions and normals
/// make_scene gives for a model whose nodes are at these positions, bit for bit. InvalidArgument if a
/// count differs from the scene's.
void move_scene(Scene& scene, std::span<const Vec3> master, std::span<const Vec3> slaves);

struct SceneResult {
  std::vector<NodeSegmentPair> pairs;                    ///< one per slave node, in increasing slave id
  long found = 0;                                        ///< pairs with status kFound
  long no_segment = 0;                                   ///< pairs with status kNoSegment
  std::array<long, kStatusCount> label_status_counts{};  ///< labels of the found pairs, by Status
  ShapeStatistics statistics;                            ///< over the found pairs
};

/// The global search options.search chooses (surface or nearest node) over every slave node of the scene,
/// counts and statistics.
[[nodiscard]] SceneResult search_scene(const Scene& scene, const SearchOptions& options);

/// The master surface's faces in the deck's order, by element id and then face number: the order in which an
/// FE code lists them to the contact search handle (contact_search.hpp), as the tests, the MPI checks and the
/// Python module give them.
[[nodiscard]] std::vector<int> master_faces_in_deck_order(const Scene& scene);

/// The largest |gap| of the found pairs (statuses ok and outside) divided by the shortest edge of the pair's
/// segment: how far from its segments the scene's own slave nodes lie (0 when no pair has a gap).
[[nodiscard]] double largest_relative_offset(const SceneResult& result);

}  // namespace contactnn::contact
