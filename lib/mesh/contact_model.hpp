// A deck's contact pairs: the solid mesh, its surfaces and the *CONTACT PAIR lines (SPEC 7), as read by
// io::read_inp_deck, and the two sides of one pair: the master surface's faces and the slave nodes.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/solid_mesh.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::mesh {

/// TYPE= of a *SURFACE. kUnsupported: any other type (SEGMENTS, CYLINDER, ... of analytic rigid
/// surfaces): kept so that a pair using it can be refused with a clear message.
enum class SurfaceType { kElement, kNode, kUnsupported };

struct SurfaceDefinition {
  std::string name;  ///< as first spelled in the deck
  SurfaceType type = SurfaceType::kElement;
  std::string type_text;           ///< the TYPE= value as written (for messages)
  std::vector<ElementFace> faces;  ///< kElement: element faces, in deck order
  std::vector<int> nodes;          ///< kNode: node indices, in deck order (repeats possible)
  std::string where;               ///< "'file':line" of its first *SURFACE line
};

/// One data line of a *CONTACT PAIR block: "slave, master" (the role is the position, never the name).
struct ContactPairDefinition {
  std::string slave_name, master_name;  ///< as written
  int slave = -1;                       ///< index into ContactModel::surfaces
  int master = -1;                      ///< index into ContactModel::surfaces (an element surface)
  bool node_to_surface = true;          ///< TYPE=NODE TO SURFACE (CalculiX's default) or SURFACE TO SURFACE
  std::string where;                    ///< "'file':line" of the data line
};

/// A *CYCLIC SYMMETRY MODEL with its *TIE, CYCLIC SYMMETRY: the deck is one sector of `sectors`, repeated
/// about the axis through axis_a and axis_b; the tie names the sector's two cut faces. A contact pair
/// between those two surfaces is a contact between a sector and its neighbour (contact::make_scene).
struct CyclicSymmetry {
  int sectors = 0;
  Vec3 axis_a = Vec3::Zero(), axis_b = Vec3::Zero();
  std::string tie;                     ///< the tie's NAME
  std::string dependent, independent;  ///< its surfaces, as written
  std::string where;                   ///< "'file':line" of the *CYCLIC SYMMETRY MODEL line
};

struct ContactModel {
  SolidMesh mesh;
  std::vector<SurfaceDefinition> surfaces;
  std::vector<ContactPairDefinition> pairs;  ///< in file order; SPEC 7's K indexes this from 0
  std::vector<CyclicSymmetry> cyclic;        ///< in file order
};

/// Pair `k`. InvalidArgument (exit 2) naming the number of pairs if `k` is out of range.
[[nodiscard]] const ContactPairDefinition& contact_pair(const ContactModel& model, int k);

/// The master surface of pair `k` as segments (build_surface_mesh over its faces). FormatError naming
/// the pair's line if the master is not an element surface.
[[nodiscard]] SurfaceMesh master_surface(const ContactModel& model, int k);

/// The slave nodes of a pair: a node surface's nodes, or every node of an element surface's faces (the faces
/// of build_surface_mesh: segments and extra faces, and the nodes merged into theirs; a face it drops
/// contributes no node), mid-side nodes of quadratic faces included (SPEC 9, as CalculiX has them), minus the
/// nodes of `master` (its mid-side nodes and merged nodes included).
///
/// Two searches, two slave sets. The surface search (SPEC 9) takes every node. The paper's nearest-node
/// search keeps SPEC 7's: the corner nodes of an element surface's faces, i.e. the nodes whose `midside` flag
/// is 0 (corner_slaves). A node that is a corner of one slave face and a mid-side node of another counts as a
/// corner.
struct SlaveNodes {
  std::vector<int> nodes;  ///< SolidMesh node indices, in increasing node id, each once
  /// One per node: 1 for a mid-side node of the element surface's quadratic faces that is a corner of none of
  /// them (SPEC 9 only), 0 otherwise (always 0 for a node surface).
  std::vector<std::uint8_t> midside;
  std::map<std::string, int> skipped_faces;  ///< an element surface's faces that have no segment, by kind
  int shared_with_master = 0;                ///< nodes left out because they are also master nodes
};
/// FormatError naming the pair's line if the slave surface's TYPE is unsupported.
[[nodiscard]] SlaveNodes slave_nodes(const ContactModel& model, int k, const SurfaceMesh& master);

/// SPEC 7's slave nodes of the nearest-node search: `slaves` without its mid-side nodes (midside == 1), in
/// the same order; skipped_faces and shared_with_master as in `slaves`.
[[nodiscard]] SlaveNodes corner_slaves(const SlaveNodes& slaves);

}  // namespace contactnn::mesh
