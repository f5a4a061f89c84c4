#include "mesh/contact_model.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace contactnn::mesh {

namespace {

const SurfaceDefinition& surface_of(const ContactModel& model, const ContactPairDefinition& pair,
                                    bool master) {
  const int index = master ? pair.master : pair.slave;
  CONTACTNN_REQUIRE(
      index >= 0 && index < static_cast<int>(model.surfaces.size()),
      "contact pair at " << pair.where << " has no resolved " << (master ? "master" : "slave") << " surface");
  const SurfaceDefinition& surface = model.surfaces[static_cast<std::size_t>(index)];
  CONTACTNN_REQUIRE_AS(FormatError, surface.type != SurfaceType::kUnsupported,
                       pair.where << ": *CONTACT PAIR: " << (master ? "master" : "slave") << " surface '"
                                  << surface.name << "' (" << surface.where
                                  << ") has TYPE=" << surface.type_text
                                  << ", which contactnn does not read (SPEC 7: ELEMENT or NODE)");
  CONTACTNN_REQUIRE_AS(FormatError, !master || surface.type == SurfaceType::kElement,
                       pair.where << ": *CONTACT PAIR: master surface '" << surface.name << "' ("
                                  << surface.where
                                  << ") is a node surface; a master surface needs faces (TYPE=ELEMENT)");
  return surface;
}

}  // namespace

const ContactPairDefinition& contact_pair(const ContactModel& model, int k) {
  const auto count = static_cast<int>(model.pairs.size());
  CONTACTNN_REQUIRE_AS(InvalidArgument, count > 0, "the deck has no *CONTACT PAIR");
  CONTACTNN_REQUIRE_AS(InvalidArgument, k >= 0 && k < count,
                       "contact pair " << k << " does not exist: the deck has " << count
                                       << " (*CONTACT PAIR data lines, counted from 0: 0.." << count - 1
                                       << ")");
  return model.pairs[static_cast<std::size_t>(k)];
}

SurfaceMesh master_surface(const ContactModel& model, int k) {
  const ContactPairDefinition& pair = contact_pair(model, k);
  const SurfaceDefinition& surface = surface_of(model, pair, true);
  return build_surface_mesh(model.mesh, surface.faces);
}

SlaveNodes slave_nodes(const ContactModel& model, int k, const SurfaceMesh& master) {
  const ContactPairDefinition& pair = contact_pair(model, k);
  const SurfaceDefinition& surface = surface_of(model, pair, false);
  SlaveNodes slaves;
  std::vector<int> nodes;
  std::vector<int> corners;  // SolidMesh indices of the element surface's face corners, sorted by index
  if (surface.type == SurfaceType::kNode) {
    nodes = surface.nodes;
  } else {
    // The element surface's own faces: the same rules as for a master (a dropped face gives no node).
    const SurfaceMesh slave_surface = build_surface_mesh(model.mesh, surface.faces);
    nodes = slave_surface.mesh_nodes;
    slaves.skipped_faces = slave_surface.skipped_faces;
    for (int f = 0; f < slave_surface.face_count(); ++f) {
      for (int n : slave_surface.face_corners(f))
        corners.push_back(slave_surface.mesh_nodes[static_cast<std::size_t>(n)]);
    }
    // A node merged into another of a collapsed face is a slave node too, a corner where that one is.
    std::sort(corners.begin(), corners.end());
    const std::size_t face_corners = corners.size();
    for (const auto& [node, standing_for_it] : slave_surface.merged_nodes) {
      nodes.push_back(node);
      if (std::binary_search(corners.begin(), corners.begin() + static_cast<std::ptrdiff_t>(face_corners),
                             standing_for_it)) {
        corners.push_back(node);
      }
    }
    std::sort(corners.begin(), corners.end());
  }
  const SolidMesh& mesh = model.mesh;
  std::sort(nodes.begin(), nodes.end(), [&](int a, int b) { return mesh.node_id(a) < mesh.node_id(b); });
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  // The master's nodes: its surface nodes and the nodes merged into them.
  std::vector<int> master_nodes = master.mesh_nodes;
  for (const auto& merged : master.merged_nodes) master_nodes.push_back(merged[0]);
  std::sort(master_nodes.begin(), master_nodes.end());
  for (int n : nodes) {
    if (std::binary_search(master_nodes.begin(), master_nodes.end(), n)) {
      ++slaves.shared_with_master;
    } else {
      slaves.nodes.push_back(n);
      const bool corner =
          surface.type == SurfaceType::kNode || std::binary_search(corners.begin(), corners.end(), n);
      slaves.midside.push_back(corner ? 0 : 1);
    }
  }
  return slaves;
}

SlaveNodes corner_slaves(const SlaveNodes& slaves) {
  SlaveNodes out;
  out.skipped_faces = slaves.skipped_faces;
  out.shared_with_master = slaves.shared_with_master;
  for (std::size_t i = 0; i < slaves.nodes.size(); ++i) {
    if (i < slaves.midside.size() && slaves.midside[i] != 0) continue;
    out.nodes.push_back(slaves.nodes[i]);
    out.midside.push_back(0);
  }
  return out;
}

}  // namespace contactnn::mesh
