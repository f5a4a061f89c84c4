// A scene over its history (lib/study/scene_history.hpp): the deck moved to every increment of a hand-written
// .frd, one row per increment, errors finite, and the fraction of pairs out of a network's domain on a state
// built to lie outside it (a master face stretched to 5 times its width) and inside it once the domain is
// drawn from the whole history; a results file that is not the deck's is refused naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "study/history_fixture.hpp"
#include "study/scene_history.hpp"

namespace contactnn::study {
namespace {

namespace fs = std::filesystem;

fs::path work_dir() {
  const fs::path d =
      fs::path(::testing::TempDir()) / ("contactnn_scene_history." + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = work_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

SceneStudyOptions small_options() {
  SceneStudyOptions o;
  o.count = 4000;
  o.epochs = 5;
  o.long_epochs = 0;
  o.sizes = {4};
  o.threads = 1;
  o.train_networks = TrainNetworks::kAlways;
  return resolved(o, SurfaceKind::kBilinear);
}

struct TwoBlocks {
  mesh::ContactModel model = io::read_inp_deck(write("two-blocks.inp", fixture::kTwoBlocksDeck));
  contact::Scene rest = contact::make_scene(model, 0);
  std::vector<HistoryState> states =
      history_states(model, io::read_frd(write("two-blocks.frd", fixture::two_blocks_frd())), 0);
};

/// The network trained on `domain`, judged with closed_form (as the plan) on every state.
HistoryJudgement judged(const TwoBlocks& t, const SceneDomain& domain, NetworkTraining& training) {
  const SceneStudyOptions o = small_options();
  training = train_networks(domain, SurfaceKind::kBilinear, o, o.sizes);
  std::vector<const SceneNetwork*> networks;
  for (const SceneNetwork& n : training.tried) networks.push_back(&n);
  MethodMeasurement plan;
  plan.name = plan.method = "closed_form";
  const std::vector<HistoryMethod> methods = history_methods(networks, training.scene, {plan}, 0);
  return judge_history(t.states, SurfaceKind::kBilinear, networks, methods, o);
}

TEST(SceneHistory, StatesAreTheDeckAtEveryIncrement) {
  const TwoBlocks t;
  ASSERT_EQ(t.states.size(), 2u);
  EXPECT_EQ(t.states[0].increment, 1);
  EXPECT_EQ(t.states[1].increment, 2);
  EXPECT_DOUBLE_EQ(t.states[1].time, 2.0);
  // Increment 1 is the rest state; increment 2's master face reaches y = 5.
  double largest_y = 0.0;
  for (const auto& x : t.states[1].scene.master.positions) largest_y = std::max(largest_y, x.y());
  EXPECT_NEAR(largest_y, 5.0, 1e-12);
  for (std::size_t i = 0; i < t.rest.master.positions.size(); ++i) {
    EXPECT_NEAR((t.states[0].scene.master.positions[i] - t.rest.master.positions[i]).norm(), 0.0, 1e-12);
  }
}

TEST(SceneHistory, OneRowPerIncrementAndTheStretchedStateOutOfTheRestDomain) {
  const TwoBlocks t;
  const SceneDomain rest_domain = sample_domain(t.rest, SurfaceKind::kBilinear, small_options());
  NetworkTraining training;
  const HistoryJudgement j = judged(t, rest_domain, training);
  ASSERT_EQ(j.methods.size(), 2u);
  EXPECT_EQ(j.methods[0].name, "network[8-4-2]");
  EXPECT_TRUE(j.methods[0].scene);
  EXPECT_EQ(j.methods[1].name, "closed_form");
  EXPECT_TRUE(j.methods[1].plan);
  ASSERT_EQ(j.increments, (std::vector<int>{1, 2}));
  for (std::size_t m = 0; m < j.methods.size(); ++m) {
    ASSERT_EQ(j.cells[m].size(), 2u);
    for (const HistoryCell& c : j.cells[m]) {
      EXPECT_EQ(c.errors.rows, 4);  // the 4 slave nodes, each over the inside of the master face
      EXPECT_TRUE(std::isfinite(c.errors.stats[0].mean_abs) && std::isfinite(c.errors.stats[1].mean_abs));
    }
  }
  // The network: every pair of the rest state in its domain, every pair of the stretched state outside.
  EXPECT_EQ(j.cells[0][0].out_of_domain, 0);
  EXPECT_EQ(j.cells[0][1].out_of_domain, 4);
  EXPECT_DOUBLE_EQ(j.cells[0][1].out_of_domain_fraction(), 1.0);
  EXPECT_FALSE(j.meets(0, 1));
  // closed_form has no domain, and is exact on a flat face.
  EXPECT_EQ(j.cells[1][1].out_of_domain, 0);
  EXPECT_LT(j.cells[1][1].worse_mean(), 1e-12);
  EXPECT_TRUE(j.meets(1, 0) && j.meets(1, 1));

  // The CSV: a header and one row per method and increment; the Markdown: a table row per increment.
  const std::string csv = history_csv(j);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 2) << csv;
  EXPECT_NE(csv.find("\n2,1,2,network[8-4-2],false,true,,4,4,0,0,0,4,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",4,1,false,,,\n"), std::string::npos) << csv;  // 4 out of domain, fraction 1, missed
  // closed_form, the plan, in the surface search: exact on the flat face, so its point for every slave node.
  ASSERT_EQ(j.plan_search.size(), 2u);
  for (const history::PlanRow& p : j.plan_search) {
    EXPECT_EQ(p.by_method, 4);
    EXPECT_EQ(p.fallbacks, 0);
    EXPECT_EQ(p.refused, 0);
  }
  EXPECT_NE(csv.find("\n2,1,2,closed_form,true,false,,4,4,0,0,0,4,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",true,4,0,0\n"), std::string::npos) << csv;
  const std::string md = history_markdown(j);
  EXPECT_NE(md.find("| 2 | 1 | 2 | 4 | 4 / 0 / 0 | 4 |"), std::string::npos) << md;
  EXPECT_NE(md.find("4 (100.00%) | **missed** |"), std::string::npos) << md;
  EXPECT_NE(md.find("worst increment"), std::string::npos) << md;
}

/// The plan's method in the surface search (as replay --plan runs it): a network trained on the rest state
/// answers the rest state's pairs itself and refuses the stretched state's (out of its domain), whose exact
/// points the search takes instead: fallbacks, none refused.
TEST(SceneHistory, ThePlansNetworkInTheSurfaceSearchFallsBackOutOfItsDomain) {
  const TwoBlocks t;
  const SceneStudyOptions o = small_options();
  const SceneDomain rest_domain = sample_domain(t.rest, SurfaceKind::kBilinear, o);
  const NetworkTraining training = train_networks(rest_domain, SurfaceKind::kBilinear, o, o.sizes);
  std::vector<const SceneNetwork*> networks;
  for (const SceneNetwork& n : training.tried) networks.push_back(&n);
  MethodMeasurement plan;
  plan.name = "network[" + networks.at(0)->name + "]";
  plan.method = "network";
  plan.network = 0;
  const std::vector<HistoryMethod> methods = history_methods(networks, training.scene, {plan}, 0);
  ASSERT_EQ(methods.size(), 1u);
  ASSERT_TRUE(methods[0].plan);
  const HistoryJudgement j = judge_history(t.states, SurfaceKind::kBilinear, networks, methods, o);
  ASSERT_EQ(j.plan_search.size(), 2u);
  EXPECT_EQ(j.plan_search[0].by_method + j.plan_search[0].fallbacks, 4);
  EXPECT_GT(j.plan_search[0].by_method, 0);
  EXPECT_EQ(j.plan_search[1].by_method, 0);
  EXPECT_EQ(j.plan_search[1].fallbacks, 4);
  EXPECT_EQ(j.plan_search[0].refused + j.plan_search[1].refused, 0);
  EXPECT_NE(history_csv(j).find(",false,0,4,0\n"), std::string::npos) << history_csv(j);
  const std::string md = history_markdown(j);
  EXPECT_NE(md.find("| 0 / 4 / 0 | **missed** |"), std::string::npos) << md;
  EXPECT_NE(history_json(j).find("\"search\": {\"by_method\": "), std::string::npos);
  // A slave point the plan's search lost misses the target whatever its errors.
  HistoryJudgement lost = j;
  lost.plan_search[0].refused = 1;
  EXPECT_FALSE(lost.meets(0, 0));
}

TEST(SceneHistory, TheHistoryDomainCoversEveryIncrement) {
  const TwoBlocks t;
  std::vector<const contact::Scene*> states = {&t.rest};
  for (const HistoryState& s : t.states) states.push_back(&s.scene);
  const SceneDomain domain = sample_domain(states, SurfaceKind::kBilinear, small_options());
  NetworkTraining training;
  const HistoryJudgement j = judged(t, domain, training);
  EXPECT_EQ(j.cells[0][0].out_of_domain, 0);
  EXPECT_EQ(j.cells[0][1].out_of_domain, 0);
  // Deterministic for a seed: the same sample again.
  const SceneDomain again = sample_domain(states, SurfaceKind::kBilinear, small_options());
  EXPECT_EQ(again.train.features, domain.train.features);
}

TEST(SceneHistory, ResultsOfAnotherDeckAreRefusedNamingTheFile) {
  // Only the master block's nodes: the slave block's are used by an element and missing.
  const std::vector<long> nodes(fixture::kTwoBlocksNodes.begin(), fixture::kTwoBlocksNodes.begin() + 8);
  const auto all = fixture::two_blocks_coordinates();
  const std::vector<std::array<double, 3>> coordinates(all.begin(), all.begin() + 8);
  const std::string frd =
      write("other.frd", fixture::frd_text(nodes, coordinates, {fixture::Displacements(8, {0.0, 0.0, 0.0})}));
  const mesh::ContactModel model = io::read_inp_deck(write("two-blocks.inp", fixture::kTwoBlocksDeck));
  try {
    (void)history_states(model, io::read_frd(frd), 0);
    FAIL() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(frd), std::string::npos) << e.what();
  }
}

TEST(SceneHistory, CapturePairs) {
  // The two blocks' slave nodes lie 0.01 above the unit face: both kinds of pairs give that offset.
  const TwoBlocks t;
  SceneStudyOptions o = small_options();
  EXPECT_NEAR(sample_domain(t.rest, SurfaceKind::kBilinear, o).deck_offset, 0.01, 1e-9);
  o.capture_pairs = "surface";
  EXPECT_NEAR(sample_domain(t.rest, SurfaceKind::kBilinear, o).deck_offset, 0.01, 1e-9);
  o.capture_pairs = "nearest";
  EXPECT_THROW((void)resolved(o, SurfaceKind::kBilinear), InvalidArgument);
}

TEST(SceneHistory, DomainStatesNames) {
  EXPECT_EQ(domain_states_from_string("history"), DomainStates::kHistory);
  EXPECT_EQ(domain_states_from_string("rest"), DomainStates::kRest);
  EXPECT_EQ(domain_states_from_string("auto"), DomainStates::kAuto);
  EXPECT_EQ(to_string(DomainStates::kHistory), "history");
  EXPECT_THROW((void)domain_states_from_string("union"), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::study

namespace contactnn::study {
namespace {

// --second-layer: every size gets a second hidden layer of that width (untrained for timing, and trained).
TEST(SceneStudyNetworks, ASecondLayerBehindEverySize) {
  const TwoBlocks t;
  SceneStudyOptions o = small_options();
  o.second_layer = 6;
  const SceneDomain domain = sample_domain(t.rest, SurfaceKind::kBilinear, o);
  const std::vector<SceneNetwork> untrained = untrained_networks(domain, SurfaceKind::kBilinear, o);
  ASSERT_EQ(untrained.size(), 1u);
  EXPECT_EQ(untrained[0].network->layer_sizes(), (std::vector<int>{8, 4, 6, 2}));
  EXPECT_EQ(untrained[0].name, "8-4-6-2-untrained");
  const NetworkTraining trained = train_networks(domain, SurfaceKind::kBilinear, o, o.sizes);
  ASSERT_EQ(trained.tried.size(), 1u);
  EXPECT_EQ(trained.tried[0].network->layer_sizes(), (std::vector<int>{8, 4, 6, 2}));
  EXPECT_EQ(trained.tried[0].name, "8-4-6-2");
  EXPECT_TRUE(std::isfinite(trained.tried[0].heldout_error()));
}

}  // namespace
}  // namespace contactnn::study
