// Tests of lib/eval/timing (the harness's bookkeeping, never its speed), method_comparison and report: a
// comparison of a stand-in predictor on a small hand-built dataset writes every file and lists every method.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "eval/method_comparison.hpp"
#include "eval/placement.hpp"
#include "eval/report.hpp"
#include "io/csv.hpp"
#include "mlp/network.hpp"
#include "xml_check.hpp"

namespace contactnn::eval {
namespace {

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A network whose every weight is zero: whatever its input, it answers the same canonical coordinates (the
/// sigmoid of minus its output thresholds, unscaled), so its error on each row is known from the labels.
mlp::Network<float> constant_network() {
  mlp::Scaling scaling;
  scaling.input_min.assign(8, -2.0);
  scaling.input_max.assign(8, 2.0);
  scaling.output_min.assign(2, -1.0);
  scaling.output_max.assign(2, 1.0);
  mlp::Network<float> net({8, 3, 2}, 2.0, scaling);
  net.thresholds(1)[0] = 0.4f;
  net.thresholds(1)[1] = -0.7f;
  return net;
}

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
    const dataset::Label l = dataset::label_configuration(
        configuration_from_features(SurfaceKind::kBilinear, rows[r].data()), SurfaceKind::kBilinear);
    // A dataset holds the canonical features (SPEC 4: here z_S < 0 rows are reflected to z_S > 0).
    for (int f = 0; f < 8; ++f) set.features(i, f) = l.features[static_cast<std::size_t>(f)];
    set.labels(i, 0) = l.canonical_param[0];
    set.labels(i, 1) = l.canonical_param[1];
    set.gap(i) = l.canonical_gap;
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

TEST(StudyReport, KnownNetworkErrorsEveryMethodEveryFile) {
  const dataset::LabelledSet set = small_set();
  const geometry::TrainingDomain domain = geometry::TrainingDomain::from_features(
      SurfaceKind::kBilinear, set.features.data(), static_cast<long>(set.size()), set.status, set.filters);
  const mlp::Network<float> constant = constant_network();
  const search::NetworkModel model(constant, domain);
  // The constant answer, through mlp::predict (an independent route to lib/search's forward pass).
  std::array<double, 2> answer{};
  mlp::ForwardPass<float> pass(constant);
  mlp::predict(constant, set.features.row(0).data(), answer.data(), pass);

  ComparisonOptions options;
  options.methods = "network, newton:1, newton:5, newton:10, newton, closed_form";
  options.timing_queries = 8;
  options.timing_options.repetitions = 2;
  options.hist_bins = 10;
  const std::vector<EvaluationSet> sets = {set_from_dataset(set, "small", "small.h5", false, 1),
                                           set_from_dataset(set, "small-placed", "small.h5", true, 3)};
  const ComparisonResult result =
      compare_methods(sets, {{"constant", "8-3-2, all weights 0", &model}}, options);
  ASSERT_EQ(result.methods, (std::vector<std::string>{"network[constant]", "newton:1", "newton:5",
                                                      "newton:10", "newton", "closed_form"}));
  ASSERT_EQ(result.sets.size(), 2u);
  EXPECT_EQ(result.histogram_method, "network[constant]");
  // The network's errors are the constant minus each label; the row without a reference is excluded.
  for (const SetResult& r : result.sets) {
    const MethodErrors& net = r.errors.front();
    ASSERT_EQ(net.method, "network[constant]");
    double sum0 = 0.0, sum1 = 0.0;
    for (Eigen::Index i = 0; i < set.size(); ++i) {
      if (set.status[static_cast<std::size_t>(i)] != Status::kOk) continue;
      sum0 += answer[0] - set.labels(i, 0);
      sum1 += answer[1] - set.labels(i, 1);
    }
    const double n = static_cast<double>(set.size() - 1);
    EXPECT_EQ(net.failures_reference, 1);
    EXPECT_EQ(net.stats[0].n, set.size() - 1);
    EXPECT_NEAR(net.stats[0].mean_signed, sum0 / n, 1e-6);  // float network
    EXPECT_NEAR(net.stats[1].mean_signed, sum1 / n, 1e-6);
    EXPECT_EQ(net.out_of_domain, 0);
    // Newton with 10 steps from the centre reaches the labels on this well-shaped segment.
    const MethodErrors& n10 = r.errors[3];
    EXPECT_EQ(n10.method, "newton:10");
    EXPECT_LT(std::max(n10.stats[0].max_abs, n10.stats[1].max_abs), 1e-10);
    EXPECT_TRUE(r.timed);
    ASSERT_EQ(r.timings.size(), result.methods.size());
  }
  EXPECT_EQ(result.histograms[0].total() + result.histograms[0].excluded,
            static_cast<std::int64_t>(set.size()));

  RunInfo info;
  info.command_line = "test";
  // One folder per process: two runs of the suite on one machine must not share it.
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / ("contactnn_study_report_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  write_report(dir, result, info, options);

  const io::CsvTable errors = io::read_csv(dir / "errors.csv");
  EXPECT_EQ(errors.rows.size(), 2 * 2 * result.methods.size());  // sets x coordinates x methods
  for (const std::string& m : result.methods) {
    for (const std::string set_name : {"small", "small-placed"}) {
      for (const std::string c : {"xi", "eta"}) {
        const auto found =
            std::find_if(errors.rows.begin(), errors.rows.end(), [&](const std::vector<std::string>& row) {
              return row[errors.column("set")] == set_name && row[errors.column("method")] == m &&
                     row[errors.column("coordinate")] == c;
            });
        EXPECT_NE(found, errors.rows.end()) << set_name << " " << m << " " << c << " missing from errors.csv";
      }
    }
  }
  const io::CsvTable speed = io::read_csv(dir / "speed.csv");
  EXPECT_EQ(speed.rows.size(), 2 * result.methods.size());
  for (const auto& row : speed.rows) {
    if (row[speed.column("method")] == "newton:5") {
      EXPECT_EQ(row[speed.column("batched_per_newton_5")], "1");
    }
    EXPECT_EQ(row[speed.column("threads")], "2");
  }
  const std::string md = read_file(dir / "report.md");
  for (const std::string& m : result.methods) {
    EXPECT_NE(md.find("| " + m + " |"), std::string::npos) << m << " missing from report.md";
  }
  for (const std::string needle :
       {"seven iterations", "more than ten iterations", "Fig 4", "Machine and build", "hist_xi.svg",
        "Newton iteration counts", "Fastest method at each accuracy level", "Set `small-placed`"}) {
    EXPECT_NE(md.find(needle), std::string::npos) << needle;
  }
  for (const std::string c : {"xi", "eta"}) {
    EXPECT_EQ(contactnn::testing::xml_well_formedness_error(read_file(dir / ("hist_" + c + ".svg"))), "")
        << c;
    const io::CsvTable hist = io::read_csv(dir / ("hist_" + c + ".csv"));
    EXPECT_EQ(hist.rows.size(), static_cast<std::size_t>(options.hist_bins) + 3);
  }
  std::filesystem::remove_all(dir);
}

TEST(StudyReport, DefaultInTheMethodListStandsForTheDefaultList) {
  const dataset::LabelledSet set = small_set();
  ComparisonOptions options;
  options.methods = "default, four_triangles";
  options.max_fixed_iterations = 2;
  options.timing = false;
  const ComparisonResult result =
      compare_methods({set_from_dataset(set, "small", "small.h5", false, 1)}, {}, options);
  EXPECT_EQ(result.methods,
            (std::vector<std::string>{"closed_form", "closed_form+newton:1", "closed_form+newton:2",
                                      "closed_form+newton:3", "closed_form+newton:5", "closed_form+newton:8",
                                      "newton:1", "newton:2", "newton", "four_triangles"}));
  options.methods = "newton, default";  // newton twice
  EXPECT_THROW((void)compare_methods({set_from_dataset(set, "small", "small.h5", false, 1)}, {}, options),
               InvalidArgument);
}

TEST(StudyReport, EffectiveErrorCountsFailuresAsAWidthAndTheFastestMethodIsPicked) {
  MethodErrors accurate, failing;
  accurate.method = "slow";
  failing.method = "fast";
  for (ErrorStatistics* s : {&accurate.stats[0], &accurate.stats[1]}) {
    s->n = 100;
    s->mean_abs = 0.001;
  }
  for (ErrorStatistics* s : {&failing.stats[0], &failing.stats[1]}) {
    s->n = 90;
    s->mean_abs = 0.0;
  }
  failing.failures_method = 10;  // 10 of 100 rows fail: (0 * 90 + 10 * 2) / 100 = 0.2 in xi units
  EXPECT_NEAR(effective_mean_error(accurate, SurfaceKind::kBilinear), 0.001, 1e-15);
  EXPECT_NEAR(effective_mean_error(failing, SurfaceKind::kBilinear), 0.2, 1e-15);
  EXPECT_NEAR(effective_mean_error(failing, SurfaceKind::kGregory), 0.1, 1e-15);
  SetResult set;
  set.errors = {accurate, failing};
  Timing slow, fast;
  slow.median_ns = 50;
  fast.median_ns = 10;
  set.timings = {{"slow", slow, slow, slow}, {"fast", fast, fast, fast}};
  EXPECT_EQ(fastest_within(set, SurfaceKind::kBilinear, 0.5)->method, "fast");
  EXPECT_EQ(fastest_within(set, SurfaceKind::kBilinear, 0.01)->method, "slow");
  EXPECT_EQ(fastest_within(set, SurfaceKind::kBilinear, 1e-4), nullptr);
}

}  // namespace
}  // namespace contactnn::eval
