// A run's states (lib/history/run_states.hpp) on the two blocks of study/history_fixture.hpp and a .frd
// written here: the positions at increment N are the node block's coordinates plus N's DISP, computed here
// from the values written into the file; the states are bit for bit those of the deck moved by
// io::move_to_increment with the scene built again, and the searches answer alike; the results' rows are
// looked up once for increments that list their DISP nodes alike; a DISP without a node is refused with the
// state kept.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "contact/scene.hpp"
#include "core/error.hpp"
#include "history/run_states.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "study/history_fixture.hpp"

namespace contactnn::history {
namespace {

namespace fs = std::filesystem;
namespace fixture = study::fixture;
using geometry::Vec3;

std::string write(const std::string& name, const std::string& text) {
  const fs::path d = fs::path(::testing::TempDir()) / ("contactnn_run_states." + std::to_string(::getpid()));
  fs::create_directories(d);
  const fs::path p = d / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

/// `v` as the file holds it: E12.5, read back.
double written(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%12.5E", v);
  return std::strtod(b, nullptr);
}

/// Three increments: the rest state; the master's top nodes moved and the slave block lowered into contact;
/// a shear of every node, its DISP records in reverse order. Each value as the file holds it.
std::vector<fixture::Displacements> displacements() {
  const std::size_t n = fixture::kTwoBlocksNodes.size();
  fixture::Displacements rest(n, {0.0, 0.0, 0.0}), pressed = rest, sheared = rest;
  for (std::size_t i = 0; i < n; ++i) {
    const std::array<double, 3> x = fixture::two_blocks_coordinates()[i];
    if (x[2] == 1.0) pressed[i] = {0.0125 * x[0], -0.031 * x[1], 0.002 * x[0] * x[1]};
    if (x[2] > 1.0) pressed[i] = {0.0, 0.0, -0.015};
    sheared[i] = {written(0.05 * x[2]), written(0.01 * x[0]), written(-0.004 * x[1])};
  }
  return {rest, pressed, sheared};
}

std::vector<std::size_t> reversed() {
  std::vector<std::size_t> order;
  for (std::size_t i = fixture::kTwoBlocksNodes.size(); i-- > 0;) order.push_back(i);
  return order;
}

struct TwoBlocks {
  std::string deck = write("two-blocks.inp", fixture::kTwoBlocksDeck);
  mesh::ContactModel model = io::read_inp_deck(deck);
  io::FrdResults results = io::read_frd(
      write("three.frd", fixture::frd_text(fixture::kTwoBlocksNodes, fixture::two_blocks_coordinates(),
                                           displacements(), {{}, {}, reversed()})));
};

/// Node `id`'s expected position at increment index k: its coordinates plus its DISP, as written.
Vec3 expected(long id, std::size_t k) {
  for (std::size_t i = 0; i < fixture::kTwoBlocksNodes.size(); ++i) {
    if (fixture::kTwoBlocksNodes[i] != id) continue;
    const std::array<double, 3> x = fixture::two_blocks_coordinates()[i];
    const std::array<double, 3> d = displacements()[k][i];
    return Vec3(x[0], x[1], x[2]) + Vec3(d[0], d[1], d[2]);
  }
  ADD_FAILURE() << "node " << id << " is not in the fixture";
  return Vec3::Zero();
}

TEST(RunStates, PositionsAreTheCoordinatesPlusTheIncrementsDisp) {
  const TwoBlocks t;
  RunStates run(t.model, 0, &t.results);
  ASSERT_EQ(run.count(), 3u);
  for (std::size_t k = 0; k < run.count(); ++k) {
    const contact::Scene& s = run.move_to(k);
    EXPECT_EQ(run.current(), k);
    ASSERT_EQ(s.master.node_count(), 4);  // the lower block's top face
    for (int j = 0; j < s.master.node_count(); ++j) {
      const auto u = static_cast<std::size_t>(j);
      EXPECT_EQ(s.master.positions[u], expected(s.master.node_ids[u], k)) << "increment " << k;
    }
    ASSERT_EQ(s.slave_ids.size(), 4u);
    for (std::size_t i = 0; i < s.slave_ids.size(); ++i)
      EXPECT_EQ(s.slave_positions[i], expected(s.slave_ids[i], k)) << "increment " << k;
  }
  // The pressed state's master face: the top nodes moved by the DISP written above, (1, 1) to (1.0125,
  // 0.969).
  const contact::Scene& pressed = run.move_to(1);
  bool corner = false;
  for (const Vec3& x : pressed.master.positions)
    corner = corner || (x - Vec3(1.0125, 0.969, 1.002)).norm() < 1e-15;
  EXPECT_TRUE(corner);
}

TEST(RunStates, StatesAreTheRebuiltScenesBitForBit) {
  const TwoBlocks t;
  RunStates run(t.model, 0, &t.results);
  mesh::ContactModel moved = t.model;
  contact::SearchOptions options;
  options.surface = SurfaceKind::kGregory;  // the node normals matter
  for (const std::size_t k : {0u, 1u, 2u, 1u}) {
    const contact::Scene& s = run.move_to(k);
    io::move_to_increment(moved.mesh, t.results, k);
    const contact::Scene rebuilt = contact::make_scene(moved, 0);
    EXPECT_EQ(s.master.positions, rebuilt.master.positions);
    EXPECT_EQ(s.master_normals, rebuilt.master_normals);
    EXPECT_EQ(s.master.segments, rebuilt.master.segments);
    EXPECT_EQ(s.slave_ids, rebuilt.slave_ids);
    EXPECT_EQ(s.slave_positions, rebuilt.slave_positions);
    const contact::SceneResult a = contact::search_scene(s, options);
    const contact::SceneResult b = contact::search_scene(rebuilt, options);
    ASSERT_EQ(a.pairs.size(), b.pairs.size());
    for (std::size_t i = 0; i < a.pairs.size(); ++i) {
      EXPECT_EQ(a.pairs[i].status, b.pairs[i].status);
      EXPECT_EQ(a.pairs[i].segment, b.pairs[i].segment);
      EXPECT_EQ(a.pairs[i].point, b.pairs[i].point);
      EXPECT_EQ(a.pairs[i].label.gap, b.pairs[i].label.gap);
    }
    EXPECT_GT(a.found, 0);
  }
}

TEST(RunStates, LooksTheRowsUpOnlyWhereTheDispNodesChange) {
  const TwoBlocks t;
  RunStates run(t.model, 0, &t.results);
  EXPECT_EQ(run.lookups(), 0);
  EXPECT_EQ(run.current(), run.count());  // the deck's state
  run.move_to(0);
  run.move_to(1);
  EXPECT_EQ(run.lookups(), 1);  // increments 1 and 2 list the nodes alike
  run.move_to(2);
  EXPECT_EQ(run.lookups(), 2);  // increment 3 in reverse order
  const contact::Scene& back = run.move_to(1);
  EXPECT_EQ(run.lookups(), 3);
  for (std::size_t i = 0; i < back.slave_ids.size(); ++i)
    EXPECT_EQ(back.slave_positions[i], expected(back.slave_ids[i], 1));
}

TEST(RunStates, ADispWithoutANodeIsRefusedAndTheStateKept) {
  const TwoBlocks t;
  // Increment 2's DISP lacks node 6 (a master node): U written for a node set only.
  std::vector<std::size_t> without_6;
  for (std::size_t i = 0; i < fixture::kTwoBlocksNodes.size(); ++i) {
    if (fixture::kTwoBlocksNodes[i] != 6) without_6.push_back(i);
  }
  const io::FrdResults partial = io::read_frd(
      write("partial.frd", fixture::frd_text(fixture::kTwoBlocksNodes, fixture::two_blocks_coordinates(),
                                             displacements(), {{}, without_6})));
  RunStates run(t.model, 0, &partial);
  const std::vector<Vec3> before = run.move_to(0).master.positions;
  try {
    run.move_to(1);
    ADD_FAILURE() << "no FormatError";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("DISP of increment 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("partial.frd"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("node 6"), std::string::npos) << e.what();
  }
  EXPECT_EQ(run.scene().master.positions, before);
  EXPECT_EQ(run.current(), 0u);
  run.move_to(2);  // the walk goes on
  for (std::size_t i = 0; i < run.scene().slave_ids.size(); ++i)
    EXPECT_EQ(run.scene().slave_positions[i], expected(run.scene().slave_ids[i], 2));
}

TEST(RunStates, WithoutResultsTheDecksStateOnly) {
  const TwoBlocks t;
  RunStates run(t.model, 0, nullptr);
  EXPECT_EQ(run.count(), 0u);
  EXPECT_EQ(run.scene().slave_positions, contact::make_scene(t.model, 0).slave_positions);
  EXPECT_THROW(run.move_to(0), InvalidArgument);
  EXPECT_THROW(RunStates(t.model, 1, &t.results), InvalidArgument);  // the deck has pair 0 only
}

}  // namespace
}  // namespace contactnn::history
