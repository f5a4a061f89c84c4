// The contact search across MPI ranks (issue 41): each rank passes its own master faces and its own slave
// nodes; each rank gets, for each of its slave nodes, the closest point over the master faces of ALL ranks,
// the same answer (face, location, status, the bits of point, gap, normal, local coordinates) as the serial
// contact::ContactSearch over all the faces, whatever the rank count and the split.
//
// Input, per rank:
//  - faces: a global face id each (distinct over all ranks), a type (mesh::FaceType) and its nodes as global
//    node ids in SPEC 9's order (contact_search.hpp). SPEC 9's tie rule reads the global face id: the serial
//    handle's caller index, where the serial caller gives its faces in increasing global id.
//  - nodes: global ids and the coordinates (every update) of at least every node of the rank's faces and of
//  its
//    slave nodes. A node on several ranks (an interface node of the split) must have the same coordinates on
//    each, bit for bit.
//  - slave nodes: global ids (among the rank's nodes). A rank may have no faces, no slave nodes, or neither.
//
// What is exchanged, and when (every collective runs on a duplicate of the caller's communicator; the library
// never calls MPI_Init):
//  - At creation: the node ids and face ids each rank uses, sent to the rank `id mod P` (one MPI_Alltoallv
//    each), which finds a face id given twice and the node ids used on more than one rank (the interface
//    nodes), and tells each rank which of its nodes those are.
//  - At every update, in this order:
//    1. the interface nodes' coordinates to the rank `id mod P` (MPI_Alltoallv), which compares the copies;
//    2. one MPI_Allreduce of the local errors (sizes, non-finite coordinates, interface nodes that
//       differ): on any error every rank throws the same exception with the lowest failing rank's message
//       (MPI_Bcast), before any exchange of faces and before anything is written;
//    3. one MPI_Allreduce (3 doubles, max): the largest face size (the default capture distance is one
//       largest face size over all ranks, contact::capture_distance's definition), the growth of the faces'
//       boxes and the slave nodes' movement since the last choice of the ghost faces;
//    4. only where that movement outruns the budget (the capture distance plus a quarter of it, the reach
//       the ghost faces were chosen with), at the first update, or always with options.tracking false: the
//       box of each rank's slave nodes (MPI_Allgather, 6 doubles per rank), then the ghost layer: each rank
//       sends each other rank its faces whose bounding box (its corners' box, widened by a quadratic face's
//       bulge) meets that rank's slave box widened by the reach: ids, types, node ids (MPI_Alltoallv);
//    5. the coordinates of the ghost faces' nodes from their owners, each node once per sender
//       (MPI_Alltoallv);
//    6. the local search: a contact::ContactSearch over the rank's own faces within reach of its slaves and
//       the ghost faces, in increasing global face id, its nodes in increasing global id, fresh (the serial
//       tracker's warm starts may differ from a fresh search in the last bits);
//    7. one MPI_Allreduce of the local search's errors, then the answers are written.
//  No answer travels: every face that holds a point within the capture distance of a slave node (and so
//  every face that can win or tie, and every face sharing the edge or vertex where a closest point lies,
//  whose normals make the pseudo-normal of the gap's sign) reaches the slave node's rank, so the rank's own
//  search is the serial one restricted to faces that cannot change its answer.
//
// Not (yet) supported: Gregory quad4 surfaces (their node normals need each face's whole ring of neighbours:
// InvalidArgument), free points, and decks whose largest coordinate lies beyond 2^+-40 (the serial search's
// working unit, surface_search.hpp, is then the master's, and a rank's local master may have another: the
// answers may then differ in their last bits).
#pragma once

#include <mpi.h>

#include <memory>
#include <span>

#include "contact/contact_search.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::mpi {

/// The caller's output arrays for its m slave nodes (sizes m, 2m, 3m); an empty optional span is not written.
/// As contact::ContactResults, with the face as its global id and the rank that passed it.
struct DistributedResults {
  std::span<int> status;  ///< required: Status::kOk (0) or kNoSegment (6)
  std::span<long> face;   ///< required: global face id, -1 when none
  std::span<int> owner;   ///< rank that passed the face, -1 when none
  std::span<int> location;
  std::span<double> param;  ///< 2m
  std::span<double> point;  ///< 3m
  std::span<double> gap;
  std::span<double> normal;  ///< 3m
};

/// What the last update (or, before the first update, the creation) sent from this rank. Bytes are the
/// payloads of its all-to-all messages to other ranks and of the allgather (counted once per other rank); the
/// all-to-all of message sizes that precedes each all-to-all is counted apart (4 bytes per other rank), and
/// the allreduces (a few bytes each) are counted by number only.
struct ExchangeCounts {
  long bytes_sent = 0;
  long header_bytes_sent = 0;     ///< the message sizes each all-to-all sends first (4 bytes per other rank)
  long messages_sent = 0;         ///< non-empty payloads to other ranks (an allgather: one per other rank)
  int collectives = 0;            ///< collective calls of this rank (all-to-all, allgather, allreduce, bcast)
  int allreduces = 0;             ///< of which MPI_Allreduce
  long ghost_faces_sent = 0;      ///< faces of this rank sent to other ranks (a face sent twice counts twice)
  long ghost_faces_received = 0;  ///< faces of other ranks this rank searched
  long ghost_nodes_received = 0;  ///< coordinates received per update for the ghost faces' nodes
  long faces_searched = 0;        ///< own faces within reach plus the ghost faces
  int exchanged = 0;              ///< 1 where this update chose the ghost faces afresh, 0 where it kept them
};

class DistributedContactSearch {
 public:
  /// Collective over `comm`. `face_ids[i]`, `face_types[i]` and its nodes, concatenated in `connectivity`
  /// (4, 8, 3 or 6 global node ids by its type); `node_ids`: the global id of each node of the coordinate
  /// array the updates pass; `slave_nodes`: global node ids. Options as the serial handle's (tracking: of the
  /// ghost layer; threads: the local search's). InvalidArgument on every rank, the same message, for bad
  /// input on any: a face or node id given twice, a face or slave node naming a node the rank does not pass,
  /// a face of a bad type or with a node twice, a connectivity of the wrong length, a Gregory surface.
  DistributedContactSearch(MPI_Comm comm, std::span<const long> face_ids,
                           std::span<const mesh::FaceType> face_types, std::span<const long> connectivity,
                           std::span<const long> node_ids, std::span<const long> slave_nodes,
                           const contact::ContactSearchOptions& options = {});
  ~DistributedContactSearch();
  DistributedContactSearch(const DistributedContactSearch&) = delete;
  DistributedContactSearch& operator=(const DistributedContactSearch&) = delete;

  /// Collective. One increment: `coordinates` 3 x node_ids.size() values. On every rank the same exception
  /// (InvalidArgument for arrays of the wrong size and an interface node whose ranks disagree on its
  /// coordinates, NumericalError for a non-finite coordinate of a node a face or slave node uses) when any
  /// rank's input is bad; then nothing is written on any rank.
  void update(std::span<const double> coordinates, const DistributedResults& out);

  [[nodiscard]] int rank() const;
  [[nodiscard]] int size() const;
  /// The last update's counts; before the first update, the creation's.
  [[nodiscard]] const ExchangeCounts& counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace contactnn::mpi
