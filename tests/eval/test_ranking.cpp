// Tests of lib/eval/ranking (the Pareto front, a report's tables read back, the ranking's JSON) and
// lib/eval/frontier_plot (the frontier's SVG), on hand-made methods whose ranking is worked out here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "eval/frontier_plot.hpp"
#include "eval/ranking.hpp"
#include "eval/report.hpp"
#include "io/csv.hpp"
#include "xml_check.hpp"

namespace contactnn::eval {
namespace {

/// A method with both coordinates' mean |error| `mean` over `n` rows, `failures` failing, timed at `ns`.
void add_method(SetResult& set, const std::string& name, double mean, std::int64_t n, std::int64_t failures,
                double ns) {
  MethodErrors m;
  m.method = name;
  for (ErrorStatistics& s : m.stats) {
    s.rows = n + failures;
    s.n = n;
    s.failures = failures;
    s.mean_abs = mean;
    s.p99_abs = 2 * mean;
    s.max_abs = 3 * mean;
  }
  m.rows = n + failures;
  m.failures_method = failures;
  set.errors.push_back(m);
  Timing t;
  t.median_ns = ns;
  t.min_ns = ns / 2;
  t.repetitions = 3;
  set.timings.push_back({name, t, t, t});
  set.timed = true;
}

/// Four bilinear methods: effective means 0.1, 0.001, 0.2 (10 of 100 failing: 10 x 2 / 100) and 1/3 (1e-4 +
/// ... no: 0.01), at 10, 50, 5 and 60 ns.
SetResult four_methods() {
  SetResult set;
  set.name = "grid";
  add_method(set, "closed_form", 0.1, 100, 0, 10.0);
  add_method(set, "newton:3", 0.001, 100, 0, 50.0);
  add_method(set, "network[n]", 0.0, 90, 10, 5.0);
  add_method(set, "newton", 0.01, 100, 0, 60.0);  // slower and less accurate than newton:3: off the front
  return set;
}

TEST(ParetoFront, FastestFirstEachStrictlyMoreAccurate) {
  const SetResult set = four_methods();
  const std::vector<FrontierPoint> points = frontier_points(set, SurfaceKind::kBilinear);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_NEAR(points[2].error, 0.2, 1e-15);
  EXPECT_EQ(pareto_front(points), (std::vector<std::size_t>{2, 0, 1}));
  // A tie in time: the more accurate first, and the other is not on the front.
  const std::vector<FrontierPoint> tied = {{"a", 10.0, 0.5}, {"b", 10.0, 0.1}, {"c", 20.0, 0.1}};
  EXPECT_EQ(pareto_front(tied), (std::vector<std::size_t>{1}));
  EXPECT_TRUE(pareto_front({}).empty());
}

TEST(ReportTables, ReadBackAsWrittenAndRankedAlike) {
  ComparisonResult result;
  result.surface = SurfaceKind::kBilinear;
  result.sets = {four_methods()};
  result.sets[0].errors[1].stats[1].mean_abs = 0.001 / 3.0;  // needs all its digits
  result.timing_threads = 2;
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / ("contactnn_ranking_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  io::write_text_atomically(dir / "errors.csv", errors_csv(result));
  io::write_text_atomically(dir / "speed.csv", speed_csv(result));

  const ComparisonResult back = read_report_tables(dir);
  EXPECT_EQ(back.surface, SurfaceKind::kBilinear);
  EXPECT_EQ(back.timing_threads, 2);
  ASSERT_EQ(back.sets.size(), 1u);
  ASSERT_EQ(back.sets[0].errors.size(), 4u);
  EXPECT_EQ(back.sets[0].errors[1].stats[1].mean_abs, 0.001 / 3.0);  // exactly
  EXPECT_EQ(back.sets[0].errors[2].failures_method, 10);
  EXPECT_EQ(back.sets[0].timings[3].batched.median_ns, 60.0);
  EXPECT_EQ(back.sets[0].timings[3].batched.min_ns, 30.0);
  for (const double level : kAccuracyLevels) {
    const MethodErrors* a = fastest_within(result.sets[0], SurfaceKind::kBilinear, level);
    const MethodErrors* b = fastest_within(back.sets[0], SurfaceKind::kBilinear, level);
    EXPECT_EQ(a == nullptr ? "" : a->method, b == nullptr ? "" : b->method) << level;
  }

  // The JSON: fastest at 0.1 is closed_form (network[n] is at 0.2), at 0.03 and 0.01 and 0.003 and 1e-3
  // newton:3, below none; the front is network[n], closed_form, newton:3.
  const std::string json = ranking_json(back);
  EXPECT_NE(
      json.find("\"fastest\": [\"closed_form\", \"newton:3\", \"newton:3\", \"newton:3\", \"newton:3\", "
                "null, null]"),
      std::string::npos)
      << json;
  EXPECT_NE(json.find("\"method\": \"newton\", \"mean_abs\": [0.01, 0.01], \"effective_mean\": 0.01"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"pareto\": false}]"), std::string::npos) << json;  // newton, the last
  EXPECT_NE(json.find("\"coordinates\": [\"xi\", \"eta\"], \"domain_width\": 2"), std::string::npos) << json;

  // A method without a speed row cannot be ranked.
  ComparisonResult untimed = result;
  untimed.sets[0].timings.pop_back();
  io::write_text_atomically(dir / "speed.csv", speed_csv(untimed));
  EXPECT_THROW((void)read_report_tables(dir), FormatError);
  std::filesystem::remove_all(dir);
}

TEST(FrontierSvg, OnePointPerMethodTheFrontDrawnLabelsPlaced) {
  const SetResult set = four_methods();
  const std::vector<FrontierPoint> points = frontier_points(set, SurfaceKind::kBilinear);
  const std::string svg = frontier_svg({{"grid & more", points}, {"held-out", points}});
  EXPECT_EQ(contactnn::testing::xml_well_formedness_error(svg), "");
  const auto count = [&](const std::string& needle) {
    std::size_t n = 0;
    for (auto at = svg.find(needle); at != std::string::npos; at = svg.find(needle, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<circle"), 2 * 4 + 3u);  // points, and the legend of the 3 families present
  EXPECT_EQ(count("<polyline"), 2u);
  EXPECT_EQ(count("stroke=\"#000\" stroke-width=\"1\""), 2 * 3u);  // the front outlined
  EXPECT_EQ(count(">3</text>"), 2u);                               // newton:3 labelled 3
  EXPECT_EQ(count("grid &amp; more"), 1u);
  EXPECT_NE(svg.find("width=\"1280\" height=\"600\""), std::string::npos);
  EXPECT_EQ(count("an error of 0 is drawn"), 0u);
  const std::string zero = frontier_svg({{"z", {{"newton", 10.0, 0.0}, {"closed_form", 5.0, 0.1}}}});
  EXPECT_NE(zero.find("an error of 0 is drawn at 1e-17"), std::string::npos);
}

}  // namespace
}  // namespace contactnn::eval
