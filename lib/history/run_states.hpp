// A run's states (issue 38, item 2): one contact pair of a deck walked through the increments of a CalculiX
// run (SPEC 10), in one place for gen-configs --results, replay and scene-study --results.
//
// Contract:
//  - Built once: the pair's scene (contact::make_scene) from the deck's model as given, with its nodes where
//    the deck puts them: the master faces in their outward order, the faces' sets and adjacency, the cyclic
//    copies, the slave nodes. Nothing of it is built again: a face's outward order (the element-centroid
//    test of mesh::outward_quad_corners) is the deck's. (make_scene on a moved deck decides it again at each
//    state; the two differ only where the run distorts an element so far that the test turns: the shared
//    cycliccontact.inp, run by ccx, has 3 master faces "inside out" at its increment and none in the deck,
//    and there the deck's order is the right one: the numbering of an element does not change.)
//  - move_to(i) puts the scene at increment results.increments[i]: every master node of the pair's own
//    surface and every slave node at its node-block coordinates plus the increment's DISP (bit for bit where
//    io::move_to_increment puts the deck's node; a slave node of a node surface that no element uses and the
//    results lack keeps the deck's position), the master node normals computed again, the cyclic copies
//    rotated again (contact::move_scene). The positions and normals are those of make_scene on the deck moved
//    by io::move_to_increment, bit for bit (with the faces oriented alike), so every search on the state
//    answers as before.
//  - Where the results hold each node (io::node_rows: a map of the whole node block and the increment's
//    DISP) is looked up at the first increment moved to, and again only at an increment whose DISP lists
//    other nodes, or the same in another order, than the last one looked up (ccx writes every increment's
//    DISP in one order: once per run). A move costs the scene's nodes, not the deck's.
//  - Errors: those of make_scene at construction (InvalidArgument for a pair the deck does not have); those
//    of io::move_to_increment at move_to (FormatError naming the results file and line when a node an
//    element uses is missing from the node block or the increment's DISP; InvalidArgument for an index out
//    of range), and the scene is then left at the state it was.
//  - The caller may drop slave nodes from scene() (study::keep_corner_slaves: scene.slaves, slave_ids and
//    slave_positions kept consistent); later moves move the ones left. Nothing else of it may change.
//  - The results must outlive the object. Not thread-safe (one walk at a time).
#pragma once

#include <cstddef>
#include <vector>

#include "contact/scene.hpp"
#include "io/frd_results.hpp"
#include "mesh/contact_model.hpp"

namespace contactnn::history {

class RunStates {
 public:
  /// Pair `pair` of `model` (taken: the object keeps the deck's nodes) over the increments of `results`
  /// (null: the deck's own state only, and no increment to move to).
  RunStates(mesh::ContactModel model, int pair, const io::FrdResults* results);

  /// Increments to move to: results->increments.size(), 0 without results.
  [[nodiscard]] std::size_t count() const;
  /// The scene at increment index i (SPEC 10's N is results->increments[i].number); the state moved to.
  const contact::Scene& move_to(std::size_t i);
  /// The scene at the state moved to last (the deck's before any move).
  [[nodiscard]] const contact::Scene& scene() const { return scene_; }
  [[nodiscard]] contact::Scene& scene() { return scene_; }
  /// Index of the increment moved to last, or count() at the deck's state.
  [[nodiscard]] std::size_t current() const { return current_; }
  [[nodiscard]] const io::FrdIncrement& increment(std::size_t i) const;
  [[nodiscard]] const mesh::ContactModel& model() const { return model_; }
  /// How often io::node_rows ran (once for a run whose increments list their DISP nodes alike).
  [[nodiscard]] int lookups() const { return lookups_; }

 private:
  mesh::ContactModel model_;
  const io::FrdResults* results_;
  contact::Scene scene_;
  io::NodeRows rows_;
  const std::vector<long>* rows_disp_nodes_ = nullptr;  ///< the DISP node list rows_ was looked up for
  std::size_t current_ = 0;
  int lookups_ = 0;
  std::vector<geometry::Vec3> master_, slaves_;  ///< the positions of a move, kept between moves
};

}  // namespace contactnn::history
