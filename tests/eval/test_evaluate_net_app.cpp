// Smoke tests of the evaluate-net app on a tiny study: gen-configs makes a small dataset, a small network is
// made for it, evaluate-net writes a report (every method listed, SVG well-formed) and labels a user's CSV
// (rows and order kept, statuses right); bad command lines fail with a clear message and exit code.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app_runner.hpp"
#include "eval/placement.hpp"
#include "io/csv.hpp"
#include "io/dataset_file.hpp"
#include "io/network_file.hpp"
#include "xml_check.hpp"

namespace contactnn::eval {
namespace {

namespace fs = std::filesystem;

const fs::path kBin = CONTACTNN_BINARY_DIR;
const fs::path kSource = CONTACTNN_SOURCE_DIR;

using contactnn::testing::read_file;
using contactnn::testing::run;

class EvaluateNetApp : public ::testing::Test {
 protected:
  // One tiny dataset and network for every test of the suite (made once: the suite stays fast).
  static void SetUpTestSuite() {
    // ctest runs each test of the suite as its own process, in parallel under -j: one directory each.
    dir_ = fs::path(::testing::TempDir()) / ("contactnn_evaluate_net_app." + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string gen = (kBin / "apps/gen-configs/gen-configs").string();
    ASSERT_EQ(run(gen + " --quiet --threads 2 --output " + (dir_ / "tiny.h5").string() +
                      " --d_xy_points 8 --c_xy_points 6 --c_z_points 2 --s_xy_points 8 --s_z_points 2",
                  dir_ / "gen.log"),
              0)
        << read_file(dir_ / "gen.log");
    make_network();
  }
  // CONTACTNN_KEEP_TEST_OUTPUT=1 keeps the directory for a look at the files.
  static void TearDownTestSuite() {
    if (std::getenv("CONTACTNN_KEEP_TEST_OUTPUT") == nullptr) fs::remove_all(dir_);
  }

  /// An 8-8-2 network for the tiny dataset: trained by train-net for a few epochs where it is built, else
  /// seeded random weights with the dataset's scaling and domain. Its accuracy is irrelevant here, only
  /// that evaluate-net reads and applies a real network file.
  static void make_network() {
    const dataset::LabelledSet set = io::read_dataset(dir_ / "tiny.h5");
    set_ = set;
#ifdef CONTACTNN_HAVE_TRAIN_NET
    const std::string train = (kBin / "apps/train-net/train-net").string();
    ASSERT_EQ(run(train + " --quiet --threads 2 --data " + (dir_ / "tiny.h5").string() + " --output " +
                      (dir_ / "net.h5").string() + " --hidden 8 --epochs 20 --train_count 100 --seed 3",
                  dir_ / "train.log"),
              0)
        << read_file(dir_ / "train.log");
    domain_ = io::read_network<float>(dir_ / "net.h5").domain;
#else
    const mlp::Scaling scaling = mlp::Scaling::from_inputs(set.features, 2, -1.0, 1.0);
    mlp::Network<float> network({8, 8, 2}, 1.0, scaling);
    network.initialize(42);
    const geometry::TrainingDomain domain = geometry::TrainingDomain::from_features(
        set.surface, set.features.data(), static_cast<long>(set.size()), set.status, set.filters);
    io::write_network(dir_ / "net.h5", network, domain, io::NetworkProvenance{});
    domain_ = domain;
#endif
  }

  static std::string evaluate_net() { return (kBin / "apps/evaluate-net/evaluate-net").string(); }

  /// The tiny dataset's rows 0, step, 2 step, ... below `end`, row r placed by placement(r), as a bilinear
  /// RAW.csv `name`.csv, labelled by gen-configs (label mode) into `name`-labels.csv; its log is `log`.
  template <class Placement>
  static void labelled_raw_csv(const std::string& name, Eigen::Index end, Eigen::Index step,
                               const Placement& placement, const std::string& log) {
    std::string csv;
    for (const auto column : kRawPointColumns) csv += (csv.empty() ? "" : ",") + std::string(column);
    csv += "\n";
    for (Eigen::Index r = 0; r < end; r += step) {
      const geometry::Configuration c = place(
          configuration_from_features(SurfaceKind::kBilinear, set_.features.row(r).data()), placement(r));
      std::string line;
      for (int node = 0; node < 4; ++node) {
        for (int k = 0; k < 3; ++k) line += (line.empty() ? "" : ",") + io::format_double(c.nodes[node][k]);
      }
      for (int k = 0; k < 3; ++k) line += "," + io::format_double(c.slave[k]);
      csv += line + "\n";
    }
    std::ofstream(dir_ / (name + ".csv")) << csv;
    const std::string gen = (kBin / "apps/gen-configs/gen-configs").string();
    ASSERT_EQ(run(gen + " --surface bilinear --input " + (dir_ / (name + ".csv")).string() + " --output " +
                      (dir_ / (name + "-labels.csv")).string(),
                  dir_ / log),
              0)
        << read_file(dir_ / log);
  }

  static inline fs::path dir_;
  static inline dataset::LabelledSet set_;
  static inline geometry::TrainingDomain domain_;
};

TEST_F(EvaluateNetApp, ReportListsEveryMethodAndWritesWellFormedSvg) {
  const fs::path report = dir_ / "report";
  ASSERT_EQ(run(evaluate_net() + " --quiet --threads 2 --weights " + (dir_ / "net.h5").string() + " --data " +
                    (dir_ / "tiny.h5").string() + " --report " + report.string() +
                    " --timing_queries 200 --timing_repetitions 2",
                dir_ / "report.log"),
            0)
      << read_file(dir_ / "report.log");
  EXPECT_NE(read_file(dir_ / "report.log").find("report.md"), std::string::npos);

  // The default methods for one bilinear network named after its file, written out.
  std::vector<std::string> methods = {"network[net]"};
  for (const int k : {1, 2, 3, 5, 8}) methods.push_back("network+newton:" + std::to_string(k) + "[net]");
  methods.push_back("closed_form");
  for (const int k : {1, 2, 3, 5, 8}) methods.push_back("closed_form+newton:" + std::to_string(k));
  for (int k = 1; k <= 10; ++k) methods.push_back("newton:" + std::to_string(k));
  methods.push_back("newton");
  const io::CsvTable errors = io::read_csv(report / "errors.csv");
  ASSERT_EQ(errors.rows.size(), 2 * methods.size());
  for (std::size_t m = 0; m < methods.size(); ++m) {
    EXPECT_EQ(errors.rows[2 * m][errors.column("set")], "tiny");
    EXPECT_EQ(errors.rows[2 * m][errors.column("method")], methods[m]);
    EXPECT_EQ(errors.rows[2 * m][errors.column("coordinate")], "xi");
    EXPECT_EQ(errors.rows[2 * m + 1][errors.column("coordinate")], "eta");
    // Every row of the dataset is accounted for: in the statistics or counted as a failure.
    EXPECT_EQ(errors.number(2 * m, errors.column("rows")), static_cast<double>(set_.size()));
    EXPECT_EQ(errors.number(2 * m, errors.column("n")) + errors.number(2 * m, errors.column("failures")),
              static_cast<double>(set_.size()));
  }
  const std::string md = read_file(report / "report.md");
  for (const std::string& m : methods) EXPECT_NE(md.find("| " + m + " |"), std::string::npos) << m;
  EXPECT_NE(md.find("evaluate-net"), std::string::npos);

  const io::CsvTable speed = io::read_csv(report / "speed.csv");
  EXPECT_EQ(speed.rows.size(), methods.size());
  for (const std::string c : {"xi", "eta"}) {
    EXPECT_EQ(contactnn::testing::xml_well_formedness_error(read_file(report / ("hist_" + c + ".svg"))), "")
        << c;
    EXPECT_TRUE(fs::exists(report / ("hist_" + c + ".csv")));
  }
  EXPECT_TRUE(fs::exists(report / "evaluate-net.config.toml"));
}

TEST_F(EvaluateNetApp, SeveralNetworksAndAPairsFileInOneReport) {
  // The same network under a second name, the dataset and a labelled RAW.csv of its first rows (label mode of
  // gen-configs on raw rows): one report with both sets and both networks' methods.
  fs::copy_file(dir_ / "net.h5", dir_ / "twin.h5", fs::copy_options::overwrite_existing);
  ASSERT_NO_FATAL_FAILURE(labelled_raw_csv(
      "some", 20, 1, [](Eigen::Index) { return random_placement(5, 0); }, "label.log"));
  const fs::path report = dir_ / "report2";
  ASSERT_EQ(run(evaluate_net() + " --quiet --weights " + (dir_ / "net.h5").string() + " --weights " +
                    (dir_ / "twin.h5").string() + " --data " + (dir_ / "tiny.h5").string() + " --pairs " +
                    (dir_ / "some-labels.csv").string() + " --methods network,newton:10 --report " +
                    report.string() + " --timing_queries 100 --timing_repetitions 1",
                dir_ / "report2.log"),
            0)
      << read_file(dir_ / "report2.log");
  const io::CsvTable errors = io::read_csv(report / "errors.csv");
  ASSERT_EQ(errors.rows.size(), 2u * 3u * 2u);  // sets x methods x coordinates
  // Rows: tiny/network[net], tiny/network[twin], tiny/newton:10, then the same for some-labels; twins answer
  // alike.
  EXPECT_EQ(errors.rows[0][errors.column("method")], "network[net]");
  EXPECT_EQ(errors.rows[2][errors.column("method")], "network[twin]");
  EXPECT_EQ(errors.rows[4][errors.column("method")], "newton:10");
  EXPECT_EQ(errors.rows[0][errors.column("mean_abs")], errors.rows[2][errors.column("mean_abs")]);
  EXPECT_EQ(errors.rows[6][errors.column("set")], "some-labels");
  EXPECT_EQ(errors.number(6, errors.column("rows")), 20.0);
  // report.md's Table 1 has every network on every set (it had the first network only).
  const std::string md = read_file(report / "report.md");
  for (const std::string net : {"network[net]", "network[twin]"}) {
    for (const std::string set : {"tiny", "some-labels"}) {
      EXPECT_NE(md.find("| `" + net + "` | " + set + " |"), std::string::npos) << net << " on " << set;
    }
  }
  // The effective config reproduces the run: both networks and both sets (it kept the first of each, and
  // --newton-steps, which needs --input, so that reading it back failed).
  const fs::path again = dir_ / "report3";
  ASSERT_EQ(run(evaluate_net() + " --config " + (report / "evaluate-net.config.toml").string() +
                    " --report " + again.string(),
                dir_ / "report3.log"),
            0)
      << read_file(dir_ / "report3.log");
  EXPECT_EQ(read_file(again / "errors.csv"), read_file(report / "errors.csv"));
}

TEST_F(EvaluateNetApp, NewtonStepsAfterTheNetworkReachTheLabels) {
  // SPEC 8: --newton-steps K refines the network's estimate on the caller's segment; with enough steps the
  // answer is the reference's (gen-configs label mode) to Newton's tolerance, whatever the network.
  ASSERT_NO_FATAL_FAILURE(labelled_raw_csv(
      "steps", set_.size(), 7, [](Eigen::Index r) { return random_placement(6, r); }, "steps-label.log"));
  ASSERT_EQ(run(evaluate_net() + " --weights " + (dir_ / "net.h5").string() + " --input " +
                    (dir_ / "steps.csv").string() + " --output " + (dir_ / "steps-pred.csv").string() +
                    " --newton-steps 12",
                dir_ / "steps.log"),
            0)
      << read_file(dir_ / "steps.log");
  const io::CsvTable labels = io::read_csv(dir_ / "steps-labels.csv");
  const io::CsvTable pred = io::read_csv(dir_ / "steps-pred.csv");
  ASSERT_EQ(labels.rows.size(), pred.rows.size());
  int compared = 0;
  for (std::size_t r = 0; r < labels.rows.size(); ++r) {
    if (labels.rows[r][labels.column("status")] != "ok") continue;
    ASSERT_EQ(pred.rows[r][pred.column("status")], "ok") << "row " << r;
    EXPECT_NEAR(pred.number(r, pred.column("xi")), labels.number(r, labels.column("xi")), 1e-8)
        << "row " << r;
    EXPECT_NEAR(pred.number(r, pred.column("eta")), labels.number(r, labels.column("eta")), 1e-8)
        << "row " << r;
    ++compared;
  }
  EXPECT_GT(compared, 10);
  // Two networks in input mode: refused.
  EXPECT_EQ(run(evaluate_net() + " --weights " + (dir_ / "net.h5").string() + " --weights " +
                    (dir_ / "net.h5").string() + " --input " + (dir_ / "steps.csv").string() + " --output " +
                    (dir_ / "x.csv").string(),
                dir_ / "steps2.log"),
            2);
}

TEST_F(EvaluateNetApp, StartPlusNewtonStartsFromTheReferencesMovedByTheOffset) {
  const fs::path report = dir_ / "report-start";
  ASSERT_EQ(run(evaluate_net() + " --quiet --data " + (dir_ / "tiny.h5").string() +
                    " --methods start,start+newton:4 " + "--start_offset 0.01 --report " + report.string() +
                    " --timing_queries 100 --timing_repetitions 1",
                dir_ / "start.log"),
            0)
      << read_file(dir_ / "start.log");
  const io::CsvTable errors = io::read_csv(report / "errors.csv");
  ASSERT_EQ(errors.rows.size(), 2u * 2u);  // methods x coordinates
  EXPECT_EQ(errors.rows[0][errors.column("method")], "start[0.01 off]");
  EXPECT_EQ(errors.rows[2][errors.column("method")], "start+newton:4[0.01 off]");
  // The start alone is 0.01 off in a random direction: |du| and |dv| at most 0.01, 2 / pi of it on average.
  for (const std::size_t r : {std::size_t{0}, std::size_t{1}}) {
    EXPECT_LE(errors.number(r, errors.column("max_abs")), 0.01 + 1e-12);
    EXPECT_NEAR(errors.number(r, errors.column("mean_abs")), 0.01 * 2.0 / 3.14159265358979, 0.002);
  }
  // Four steps from there: the reference, except on the enumeration's extreme segments.
  for (const std::size_t r : {std::size_t{2}, std::size_t{3}})
    EXPECT_LT(errors.number(r, errors.column("median_abs")), 1e-12);
  EXPECT_NE(read_file(report / "report.md").find("moved 0.01 (parameter units)"), std::string::npos);
}

TEST_F(EvaluateNetApp, InputModeKeepsRowsAndOrderWithRightStatuses) {
  // Rows: in domain, out of domain (slave far above the segment), NaN, degenerate (D on the line AB),
  // in domain again; an extra column `id` must be copied through.
  std::string csv = "id";
  for (const auto name : kRawPointColumns) csv += "," + std::string(name);
  csv += "\n";
  const auto add_row = [&](const std::string& id, const geometry::Configuration& c) {
    csv += id;
    for (int node = 0; node < 4; ++node) {
      for (int k = 0; k < 3; ++k) csv += "," + io::format_double(c.nodes[node][k]);
    }
    for (int k = 0; k < 3; ++k) csv += "," + io::format_double(c.slave[k]);
    csv += "\n";
  };
  const geometry::Configuration local0 =
      configuration_from_features(SurfaceKind::kBilinear, set_.features.row(0).data());
  const geometry::Configuration local1 =
      configuration_from_features(SurfaceKind::kBilinear, set_.features.row(set_.size() - 1).data());
  add_row("first", place(local0, random_placement(11, 0)));
  geometry::Configuration far = local0;
  far.slave.z() = 1.0;
  add_row("far", place(far, random_placement(11, 1)));
  geometry::Configuration nan = local0;
  nan.slave.x() = std::nan("");
  add_row("nan", nan);
  geometry::Configuration flat = local0;
  flat.nodes[3] = geometry::Vec3(-1.0, 0.0, 0.0);
  add_row("flat", flat);
  add_row("last", place(local1, random_placement(11, 2)));
  const fs::path raw = dir_ / "raw.csv";
  std::ofstream(raw) << csv;

  const fs::path pred = dir_ / "pred.csv";
  ASSERT_EQ(run(evaluate_net() + " --weights " + (dir_ / "net.h5").string() + " --input " + raw.string() +
                    " --output " + pred.string(),
                dir_ / "input.log"),
            0)
      << read_file(dir_ / "input.log");
  const io::CsvTable out = io::read_csv(pred);
  ASSERT_EQ(out.rows.size(), 5u);
  EXPECT_EQ(out.header.front(), "id");
  const std::size_t n = out.header.size();
  EXPECT_EQ(out.header[n - 3], "xi");
  EXPECT_EQ(out.header[n - 2], "eta");
  EXPECT_EQ(out.header[n - 1], "status");
  const std::vector<std::string> ids = {"first", "far", "nan", "flat", "last"};
  const std::vector<std::string> statuses = {"ok", "out_of_domain", "invalid", "degenerate", "ok"};
  const std::vector<bool> has_value = {true, true, false, false, true};
  for (std::size_t r = 0; r < 5; ++r) {
    EXPECT_EQ(out.rows[r][0], ids[r]);
    EXPECT_EQ(out.rows[r][n - 1], statuses[r]) << ids[r];
    EXPECT_EQ(!out.rows[r][n - 3].empty(), has_value[r]) << ids[r];
    EXPECT_EQ(!out.rows[r][n - 2].empty(), has_value[r]) << ids[r];
  }
}

TEST_F(EvaluateNetApp, BadCommandLinesFailWithAClearMessage) {
  const std::string net = (dir_ / "net.h5").string();
  // No mode.
  EXPECT_EQ(run(evaluate_net() + " --weights " + net, dir_ / "bad1.log"), 2);
  EXPECT_NE(read_file(dir_ / "bad1.log").find("--data"), std::string::npos) << read_file(dir_ / "bad1.log");
  // --data without --report.
  EXPECT_EQ(
      run(evaluate_net() + " --weights " + net + " --data " + (dir_ / "tiny.h5").string(), dir_ / "bad2.log"),
      2);
  // A missing weights file.
  EXPECT_EQ(run(evaluate_net() + " --weights " + (dir_ / "missing.h5").string() + " --input x --output y",
                dir_ / "bad3.log"),
            2);
  // A dataset given as the network: wrong file kind, exit 3, the message names both kinds.
  EXPECT_EQ(run(evaluate_net() + " --weights " + (dir_ / "tiny.h5").string() + " --data " +
                    (dir_ / "tiny.h5").string() + " --report " + (dir_ / "r").string(),
                dir_ / "bad4.log"),
            3);
  EXPECT_NE(read_file(dir_ / "bad4.log").find("contactnn-network"), std::string::npos)
      << read_file(dir_ / "bad4.log");
  // An unknown key in the [evaluate-net] section of a config file.
  const fs::path config = dir_ / "bad.toml";
  std::ofstream(config) << "[evaluate-net]\nhist_binz = 10\n";
  EXPECT_EQ(run(evaluate_net() + " --config " + config.string() + " --weights " + net + " --input " +
                    (dir_ / "tiny.h5").string() + " --output " + (dir_ / "p.csv").string(),
                dir_ / "bad5.log"),
            2);
  EXPECT_NE(read_file(dir_ / "bad5.log").find("hist_binz"), std::string::npos)
      << read_file(dir_ / "bad5.log");
  // A method that refines the caller's own starts: an evaluation set has none.
  EXPECT_EQ(run(evaluate_net() + " --weights " + net + " --data " + (dir_ / "tiny.h5").string() +
                    " --report " + (dir_ / "r6").string() + " --methods network,start+newton:2",
                dir_ / "bad6.log"),
            2);
  EXPECT_NE(read_file(dir_ / "bad6.log").find("start+newton:2' refines the caller's own starts"),
            std::string::npos)
      << read_file(dir_ / "bad6.log");
}

}  // namespace
}  // namespace contactnn::eval
