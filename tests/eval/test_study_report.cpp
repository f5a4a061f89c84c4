// Tests of lib/eval/timing (the harness's bookkeeping, never its speed), study and report: a study of a
// stand-in predictor on a small hand-built dataset writes every file and lists every method.
#include <gtest/gtest.h>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "eval/report.hpp"
#include "eval/study.hpp"
#include "io/csv.hpp"
#include "xml_check.hpp"

namespace contactnn::eval {
namespace {

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Returns the label itself plus a fixed offset: a "network" with a known error of +0.01 in xi, -0.02 in eta.
struct OffsetPredictor {
  void predict(const double* features, double* out) {
    const geometry::Configuration c = configuration_from_features(SurfaceKind::kBilinear, features);
    const dataset::Label l = dataset::label_configuration(c, SurfaceKind::kBilinear);
    out[0] = l.param[0] + 0.01;
    out[1] = l.param[1] - 0.02;
  }
};

dataset::LabelledSet small_set() {
  // A 3 x 3 x 2 grid of slave positions over one segment; every label computed by the reference solver.
  std::vector<std::array<double, 8>> rows;
  for (const double xs : {0.15, 0.35, 0.45}) {
    for (const double ys : {0.1, 0.3, 0.45}) {
      for (const double zs : {-0.2, 0.15}) rows.push_back({1.05, 0.95, 0.1, -0.05, 0.9, xs, ys, zs});
    }
  }
  dataset::LabelledSet set;
  set.resize(static_cast<Eigen::Index>(rows.size()), SurfaceKind::kBilinear);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<Eigen::Index>(r);
    const dataset::Label l =
        dataset::label_configuration(configuration_from_features(SurfaceKind::kBilinear, rows[r].data()),
                                     SurfaceKind::kBilinear);
    // A dataset holds the canonical features (SPEC 4: here z_S < 0 rows are reflected to z_S > 0).
    for (int f = 0; f < 8; ++f) set.features(i, f) = l.features[static_cast<std::size_t>(f)];
    set.labels(i, 0) = l.param[0];
    set.labels(i, 1) = l.param[1];
    set.gap(i) = l.gap;
    set.iterations(i) = l.iterations;
    set.status[r] = l.status;
    set.scale(i) = 1.0;
  }
  set.status[4] = Status::kNoConvergence;  // one row without a reference: counted, never averaged in
  return set;
}

TEST(TimeMethods, RunsWarmupAndRepetitionsRoundRobin) {
  std::vector<std::string> calls;
  std::vector<TimedMethod> methods;
  for (const std::string name : {"a", "b"}) {
    methods.push_back({name, "test method", 10, [&calls, name]() {
                         calls.push_back(name);
                         return 1.0;
                       }});
  }
  TimingOptions options;
  options.repetitions = 3;
  options.warmup_passes = 2;
  const std::vector<Timing> t = time_methods(methods, options);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].samples_ns.size(), 3u);
  EXPECT_LE(t[0].min_ns, t[0].median_ns);
  EXPECT_LE(t[0].median_ns, t[0].max_ns);
  // Warm-up per method first, then the timed passes interleaved a, b, a, b, a, b.
  EXPECT_EQ(calls, (std::vector<std::string>{"a", "a", "b", "b", "a", "b", "a", "b", "a", "b"}));
  methods[1].queries = 0;
  EXPECT_THROW((void)time_methods(methods, options), InvalidArgument);
}

TEST(FitLine, ExactLineAndBadInput) {
  const std::vector<double> x = {1, 2, 3, 4};
  const std::vector<double> y = {12.5, 15.0, 17.5, 20.0};  // 10 + 2.5 x
  const LinearFit f = fit_line(x, y);
  EXPECT_NEAR(f.intercept, 10.0, 1e-12);
  EXPECT_NEAR(f.slope, 2.5, 1e-12);
  EXPECT_NEAR(f.r_squared, 1.0, 1e-12);
  EXPECT_THROW((void)fit_line(std::vector<double>{1, 1}, std::vector<double>{2, 3}), InvalidArgument);
}

TEST(StudyReport, ListsEveryMethodAndWritesEveryFile) {
  const dataset::LabelledSet set = small_set();
  const geometry::TrainingDomain domain = geometry::TrainingDomain::from_features(
      SurfaceKind::kBilinear, set.features.data(), static_cast<long>(set.size()), set.status, set.filters);
  StudyOptions options;
  options.timing_queries = 8;
  options.timing_options.repetitions = 2;
  options.hist_bins = 10;
  const StudyResult result = run_study(set, OffsetPredictor{}, domain, options);

  // The network's errors are the known offsets; the failed reference row is excluded.
  const MethodErrors& net = result.errors.front();
  ASSERT_EQ(net.method.name(), "network");
  EXPECT_EQ(net.failures_reference, 1);
  EXPECT_EQ(net.stats[0].n, static_cast<std::int64_t>(set.size()) - 1);
  EXPECT_NEAR(net.stats[0].mean_signed, 0.01, 1e-12);
  EXPECT_NEAR(net.stats[1].mean_signed, -0.02, 1e-12);
  EXPECT_EQ(result.network_out_of_domain, 0);
  EXPECT_EQ(result.histograms[0].total() + result.histograms[0].excluded, static_cast<std::int64_t>(set.size()));

  RunInfo info;
  info.network_summary = "stand-in";
  info.command_line = "test";
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "contactnn_study_report";
  std::filesystem::remove_all(dir);
  write_report(dir, result, info, options);

  const io::CsvTable errors = io::read_csv(dir / "errors.csv");
  std::vector<std::string> error_methods;
  for (const auto& row : errors.rows) error_methods.push_back(row[errors.column("method")] + "/" + row[errors.column("coordinate")]);
  for (const Method& m : error_table_methods(options.max_fixed_iterations)) {
    for (const std::string c : {"xi", "eta"}) {
      EXPECT_NE(std::find(error_methods.begin(), error_methods.end(), m.name() + "/" + c), error_methods.end())
          << m.name() << " " << c << " missing from errors.csv";
    }
  }
  EXPECT_EQ(errors.rows.size(), 2 * error_table_methods(options.max_fixed_iterations).size());

  const io::CsvTable speed = io::read_csv(dir / "speed.csv");
  std::vector<std::string> speed_methods;
  for (const auto& row : speed.rows) speed_methods.push_back(row[0]);
  for (const std::string name : {"network", "network_forward_only", "network_with_domain_check", "newton_1", "newton_5",
                                 "newton_10", "newton_converged", "reference"}) {
    EXPECT_NE(std::find(speed_methods.begin(), speed_methods.end(), name), speed_methods.end()) << name;
  }
  // ratio_to_newton_5 of newton_5 is 1 by definition.
  for (const auto& row : speed.rows) {
    if (row[0] == "newton_5") {
      EXPECT_EQ(row[speed.column("ratio_to_newton_5")], "1");
    }
  }

  const std::string md = read_file(dir / "report.md");
  for (const Method& m : error_table_methods(options.max_fixed_iterations)) {
    EXPECT_NE(md.find("| " + m.name() + " |"), std::string::npos) << m.name() << " missing from report.md";
  }
  for (const std::string needle : {"seven iterations", "more than ten iterations", "Fig 4", "Machine and build",
                                   "hist_xi.svg", "Newton iteration counts"}) {
    EXPECT_NE(md.find(needle), std::string::npos) << needle;
  }
  for (const std::string c : {"xi", "eta"}) {
    EXPECT_EQ(contactnn::testing::xml_well_formedness_error(read_file(dir / ("hist_" + c + ".svg"))), "") << c;
    const io::CsvTable hist = io::read_csv(dir / ("hist_" + c + ".csv"));
    EXPECT_EQ(hist.rows.size(), static_cast<std::size_t>(options.hist_bins) + 3);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace contactnn::eval
