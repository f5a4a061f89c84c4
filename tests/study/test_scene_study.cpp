// The scene study's policy (lib/study/scene_study.hpp) on measurements written out here: the plan is the
// fastest method that reaches the target (the most accurate when none does), and a network size is trained
// only where its network could be faster than what already reaches the target. The options' surface defaults
// and their checks.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "study/scene_domain.hpp"
#include "study/scene_report.hpp"

namespace contactnn::study {
namespace {

MethodMeasurement measured(const std::string& name, double effective, double ns, bool reaches,
                           int network = -1) {
  return {.name = name,
          .method = name.substr(0, name.find('[')),
          .network = network,
          .errors = {},
          .effective_mean = effective,
          .batched_ns = ns,
          .reaches = reaches};
}

TEST(ChoosePlan, FastestAmongThoseThatReachTheTarget) {
  const std::vector<MethodMeasurement> m = {
      measured("closed_form", 0.01, 20, false), measured("closed_form+newton:1", 1e-4, 60, true),
      measured("newton:3", 1e-3, 50, true), measured("network[16-16-2]", 5e-3, 30, false, 0),
      measured("network+newton:1[16-16-2]", 1e-5, 80, true, 0)};
  EXPECT_EQ(choose_plan(m), 2u);  // newton:3: the faster of the three that reach, not the most accurate
}

TEST(ChoosePlan, TimesWithinTheNoiseKeepTheEarlierMethod) {
  // newton:4 measured 5% faster than newton:2 (noise: it does twice the work): newton:2, listed first.
  const std::vector<MethodMeasurement> m = {
      measured("closed_form", 0.01, 20, false), measured("newton:2", 1e-6, 40, true),
      measured("newton:4", 1e-6, 38, true), measured("network+newton:1[8-8-2]", 1e-6, 30, true, 0)};
  EXPECT_EQ(choose_plan(m), 3u);  // 25% faster than newton:2: the network's
  EXPECT_EQ(choose_plan({m[0], m[1], m[2]}), 1u);
}

TEST(ChoosePlan, MostAccurateWhenNoneReaches) {
  const std::vector<MethodMeasurement> m = {
      measured("closed_form", 0.01, 20, false), measured("newton:1", 0.004, 30, false),
      measured("newton:2", 0.004, 25, false), measured("newton:5", 0.006, 50, false)};
  EXPECT_EQ(choose_plan(m), 2u);  // newton:1 and newton:2 tie in accuracy: the faster
  EXPECT_THROW((void)choose_plan({}), InvalidArgument);
}

SceneNetwork untrained(int hidden) {
  SceneNetwork n;
  n.hidden = hidden;
  n.name = "8-" + std::to_string(hidden) + "-2-untrained";
  return n;
}

TEST(SizesThatMayPay, OnlySizesFasterThanWhatReachesTheTarget) {
  SceneStudyOptions o = resolved({}, SurfaceKind::kBilinear);
  const std::vector<SceneNetwork> nets = {untrained(8), untrained(16), untrained(32)};
  std::vector<MethodMeasurement> m = {measured("closed_form", 0.01, 20, false),
                                      measured("newton:2", 1e-4, 40, true),
                                      measured("network[8-8-2-untrained]", 0.3, 35, false, 0),
                                      measured("network[8-16-2-untrained]", 0.3, 41, false, 1),
                                      measured("network[8-32-2-untrained]", 0.3, 55, false, 2)};
  std::vector<std::string> why;
  EXPECT_EQ(sizes_that_may_pay(m, nets, o, &why), std::vector<int>({8}));
  ASSERT_EQ(why.size(), 2u);
  EXPECT_NE(why[0].find("8-16-2 not trained"), std::string::npos) << why[0];
  EXPECT_NE(why[0].find("newton:2"), std::string::npos) << why[0];
  // Nothing reaches the target: every size may pay.
  m[1].reaches = false;
  EXPECT_EQ(sizes_that_may_pay(m, nets, o, nullptr), std::vector<int>({8, 16, 32}));
  // always and never.
  m[1].reaches = true;
  o.train_networks = TrainNetworks::kAlways;
  EXPECT_EQ(sizes_that_may_pay(m, nets, o, nullptr), std::vector<int>({8, 16, 32}));
  o.train_networks = TrainNetworks::kNever;
  EXPECT_TRUE(sizes_that_may_pay(m, nets, o, nullptr).empty());
}

TEST(SceneStudyOptions, SurfaceDefaultsAndChecks) {
  const SceneStudyOptions b = resolved({}, SurfaceKind::kBilinear);
  EXPECT_EQ(b.sizes, std::vector<int>({8, 16, 32}));
  EXPECT_EQ(b.target, 0.005);
  EXPECT_EQ(b.learning_rate, 0.02);
  EXPECT_NE(b.methods.find("closed_form+newton:1"), std::string::npos);
  const SceneStudyOptions g = resolved({}, SurfaceKind::kGregory);
  EXPECT_EQ(g.sizes, std::vector<int>({16, 32, 48}));
  EXPECT_EQ(g.target, 0.0025);
  EXPECT_EQ(g.learning_rate, 0.01);
  EXPECT_EQ(g.methods.find("four_triangles"), std::string::npos);  // a bilinear method only
  SceneStudyOptions bad;
  bad.sizes = {32, 16};
  EXPECT_THROW((void)resolved(bad, SurfaceKind::kBilinear), InvalidArgument);
  bad = {};
  bad.methods = "closed_form,network";
  EXPECT_THROW((void)resolved(bad, SurfaceKind::kBilinear), InvalidArgument);
  bad = {};
  bad.network_methods = "newton:2";
  EXPECT_THROW((void)resolved(bad, SurfaceKind::kBilinear), InvalidArgument);
  bad = {};
  bad.count = 99;
  EXPECT_THROW((void)resolved(bad, SurfaceKind::kBilinear), InvalidArgument);
  EXPECT_EQ(train_networks_from_string("always"), TrainNetworks::kAlways);
  EXPECT_THROW((void)train_networks_from_string("sometimes"), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::study
