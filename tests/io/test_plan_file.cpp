// The scene plan file (lib/io/plan_file.hpp): a round trip keeps every value, and the reader is strict: an
// unknown key or table, a missing field, a wrong type, a method that does not parse, a network given to a
// method without one (or missing for a network method) are errors naming the file, the line and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "error_message.hpp"
#include "io/plan_file.hpp"

namespace contactnn::io {
namespace {

/// A valid plan, written out by hand (the format of plan.hpp's header comment), line numbers as in the file.
const std::string kPlanText =
    "[plan]\n"                                  // 1
    "schema_version = 1\n"                      // 2
    "surface = \"gregory\"\n"                   // 3
    "method = \"network+newton:1\"\n"           // 4
    "network = \"net/scene.h5\"\n"              // 5
    "target = 0.0025\n"                         // 6
    "margin = 0.8\n"                            // 7
    "reached = true\n"                          // 8
    "\n"                                        // 9
    "[domain]\n"                                // 10
    "deck = \"decks/hertz.inp\"\n"              // 11
    "pair = 1\n"                                // 12
    "deformation = 0.1\n"                       // 13
    "capture = 1\n"                             // 14: an integer where a real is expected
    "normal_tilt_tangent = 0.1\n"               // 15
    "boundary_fraction = 0.2\n"                 // 16
    "heldout_count = 15000\n"                   // 17
    "heldout_seed = 1001\n"                     // 18
    "\n"                                        // 19
    "[[measurement]]\n"                         // 20
    "method = \"closed_form\"\n"                // 21
    "mean_abs = [0.01, 0.02]\n"                 // 22
    "effective_mean = 0.02\n"                   // 23
    "max_abs = 0.3\n"                           // 24
    "failures = 2\n"                            // 25
    "batched_ns = 28.5\n"                       // 26
    "reaches_target = false\n"                  // 27
    "\n"                                        // 28
    "[[measurement]]\n"                         // 29
    "method = \"network+newton:1[16-16-2]\"\n"  // 30
    "mean_abs = [1e-5, 2e-5]\n"                 // 31
    "effective_mean = 2e-5\n"                   // 32
    "max_abs = 0.001\n"                         // 33
    "failures = 0\n"                            // 34
    "batched_ns = 89\n"                         // 35
    "reaches_target = true\n";                  // 36

/// kPlanText with line `line` (1-based) replaced by `text` ("" removes it).
std::string with_line(int line, const std::string& text) {
  std::string out;
  int n = 0;
  std::size_t start = 0;
  while (start < kPlanText.size()) {
    const std::size_t end = kPlanText.find('\n', start);
    ++n;
    const std::string current = kPlanText.substr(start, end - start);
    if (n != line) {
      out += current + "\n";
    } else if (!text.empty()) {
      out += text + "\n";
    }
    start = end + 1;
  }
  return out;
}

/// The FormatError message of parsing `text` as "plan.toml" ("" when it parses).
std::string error_of(const std::string& text) {
  return testing::error_message<FormatError>([&] { (void)parse_plan(text, "plan.toml"); }, "");
}

/// Whether the FormatError of parsing `text` names `part` (its message says what it was otherwise).
::testing::AssertionResult error_names(const std::string& text, const std::string& part) {
  const std::string message = error_of(text);
  if (message.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the error '" << message << "' does not name '" << part << "'";
}

TEST(ScenePlan, ReadsEveryFieldOfAHandWrittenPlan) {
  const ScenePlan p = parse_plan(kPlanText, "plan.toml");
  EXPECT_EQ(p.surface, SurfaceKind::kGregory);
  EXPECT_EQ(p.method, "network+newton:1");
  EXPECT_EQ(p.network, "net/scene.h5");
  EXPECT_EQ(p.target, 0.0025);
  EXPECT_EQ(p.margin, 0.8);
  EXPECT_TRUE(p.reached);
  EXPECT_EQ(p.domain.deck, "decks/hertz.inp");
  EXPECT_EQ(p.domain.pair, 1);
  EXPECT_EQ(p.domain.capture, 1.0);
  EXPECT_EQ(p.domain.heldout_count, 15000);
  EXPECT_EQ(p.domain.heldout_seed, 1001);
  // Keys a plan of before the history study lacks: the rest state, the segment test on.
  EXPECT_TRUE(p.domain.segment_test);
  EXPECT_EQ(p.domain.states, "rest");
  EXPECT_EQ(p.domain.results, "");
  ASSERT_EQ(p.measurements.size(), 2u);
  EXPECT_EQ(p.measurements[0].method, "closed_form");
  EXPECT_EQ(p.measurements[0].mean_abs[1], 0.02);
  EXPECT_EQ(p.measurements[0].failures, 2);
  EXPECT_FALSE(p.measurements[0].reaches_target);
  EXPECT_EQ(p.measurements[1].batched_ns, 89.0);
  EXPECT_TRUE(p.measurements[1].reaches_target);
}

TEST(ScenePlan, WrittenPlanReadsBackToTheSameValues) {
  ScenePlan p = parse_plan(kPlanText, "plan.toml");
  p.target = 1.0 / 3.0;  // a value that needs all 17 digits
  p.domain.deck = "a \"quoted\" \\ path\twith a tab.inp";
  p.measurements[1].mean_abs[0] = 5e-324;
  p.domain.segment_test = false;
  p.domain.states = "history";
  p.domain.results = "runs/hertz-slide.frd";
  const ScenePlan q = parse_plan(plan_to_toml(p), "written.toml");
  EXPECT_FALSE(q.domain.segment_test);
  EXPECT_EQ(q.domain.states, "history");
  EXPECT_EQ(q.domain.results, "runs/hertz-slide.frd");
  // states is "rest" or "history", named with its line when not.
  std::string text = plan_to_toml(p);
  text.replace(text.find("states = \"history\""), 18, "states = \"later\"");
  try {
    (void)parse_plan(text, "states.toml");
    ADD_FAILURE() << "states = \"later\" accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("'states.toml':"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("key 'states' in [domain]"), std::string::npos) << e.what();
  }
  EXPECT_EQ(q.target, p.target);
  EXPECT_EQ(q.domain.deck, p.domain.deck);
  EXPECT_EQ(q.method, p.method);
  EXPECT_EQ(q.network, p.network);
  ASSERT_EQ(q.measurements.size(), p.measurements.size());
  for (std::size_t i = 0; i < p.measurements.size(); ++i) {
    EXPECT_EQ(q.measurements[i].method, p.measurements[i].method);
    EXPECT_EQ(q.measurements[i].mean_abs[0], p.measurements[i].mean_abs[0]);
    EXPECT_EQ(q.measurements[i].effective_mean, p.measurements[i].effective_mean);
    EXPECT_EQ(q.measurements[i].failures, p.measurements[i].failures);
    EXPECT_EQ(q.measurements[i].reaches_target, p.measurements[i].reaches_target);
  }
}

TEST(ScenePlan, UnknownKeyNamesFileLineAndKey) {
  EXPECT_EQ(error_of(with_line(7, "colour = \"blue\"")),
            "'plan.toml':7: unknown key 'colour' in [plan] (expected one of: schema_version, surface, "
            "method, network, "
            "target, margin, reached)");
  EXPECT_TRUE(error_names(with_line(25, "failures = 0\nspeed = 3"),
                          "'plan.toml':26: unknown key 'speed' in "
                          "[[measurement]] 1"));
}

TEST(ScenePlan, MissingFieldNamesFileAndKey) {
  const std::string e = error_of(with_line(4, ""));  // no method
  EXPECT_NE(e.find("'plan.toml':"), std::string::npos) << e;
  EXPECT_NE(e.find("[plan] has no key 'method' (required)"), std::string::npos) << e;
  EXPECT_TRUE(error_names(with_line(22, ""), "[[measurement]] 1 has no key 'mean_abs'"));
  // A missing table.
  EXPECT_TRUE(error_names(kPlanText.substr(0, kPlanText.find("[domain]")), "no [domain] table"));
}

TEST(ScenePlan, WrongTypesAndValuesAreRefused) {
  EXPECT_EQ(error_of(with_line(6, "target = \"small\"")),
            "'plan.toml':6: key 'target' in [plan]: expected a number");
  EXPECT_EQ(error_of(with_line(6, "target = 0")),
            "'plan.toml':6: key 'target' in [plan]: expected a number > 0");
  EXPECT_EQ(error_of(with_line(12, "pair = 1.5")),
            "'plan.toml':12: key 'pair' in [domain]: expected an integer");
  EXPECT_EQ(error_of(with_line(8, "reached = 1")),
            "'plan.toml':8: key 'reached' in [plan]: expected true or false");
  EXPECT_EQ(error_of(with_line(2, "schema_version = 2")),
            "'plan.toml':2: key 'schema_version' in [plan]: 2, this version reads 1");
  EXPECT_TRUE(error_names(with_line(3, "surface = \"quadratic\""), "'plan.toml':3: key 'surface' in [plan]"));
  EXPECT_TRUE(error_names(with_line(22, "mean_abs = [0.01]"),
                          "'plan.toml':22: key 'mean_abs' in [[measurement]] 1: "
                          "expected an array of 2 numbers"));
  EXPECT_TRUE(error_names(kPlanText + "[extra]\nx = 1\n", "unknown table [extra]"));
  EXPECT_TRUE(error_names("[plan\n", "'plan.toml':1: not valid TOML"));
}

TEST(ScenePlan, MethodAndNetworkMustAgree) {
  EXPECT_TRUE(error_names(with_line(4, "method = \"newton:x\""), "'plan.toml':4: key 'method' in [plan]"));
  // A network method without a network file, and a network file for a method that uses none.
  EXPECT_TRUE(error_names(with_line(5, "network = \"\""),
                          "'plan.toml':5: key 'network' in [plan]: method "
                          "'network+newton:1' needs a network file"));
  EXPECT_TRUE(error_names(with_line(4, "method = \"closed_form\""),
                          "'plan.toml':5: key 'network' in [plan]: method "
                          "'closed_form' uses no network"));
}

TEST(ScenePlan, NetworkPathIsRelativeToThePlan) {
  ScenePlan p = parse_plan(kPlanText, "plan.toml");
  EXPECT_EQ(plan_network_path(p, "/studies/hertz/plan.toml"),
            std::filesystem::path("/studies/hertz/net/scene.h5"));
  p.network = "/elsewhere/n.h5";
  EXPECT_EQ(plan_network_path(p, "/studies/hertz/plan.toml"), std::filesystem::path("/elsewhere/n.h5"));
  p.network.clear();
  EXPECT_TRUE(plan_network_path(p, "/studies/hertz/plan.toml").empty());
}

TEST(ScenePlan, MissingFileIsAnIoError) {
  EXPECT_THROW((void)read_plan("/nonexistent/contactnn/plan.toml"), IoError);
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "contactnn_test_plan.toml";
  std::ofstream(path) << with_line(7, "colour = 1");
  try {
    (void)read_plan(path);
    FAIL() << "a plan with an unknown key was read";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + path.string() + "':7: unknown key 'colour'"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace contactnn::io
