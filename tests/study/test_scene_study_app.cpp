// The compiled scene-study on the example scenes (scripts/make-scene, the example_scenes fixture) with small
// settings: the plan file parses; evaluate-net --plan gives, row by row, what the plan's method gives through
// lib/search here; the plan's method reaches the target on the deck's pairs inside a face and no method the
// study measured reaches it faster; the flat scene gets a plan without a network; a malformed plan (unknown
// key, missing field) is refused naming the file, the line and the key. With --results (issue 29): a row per
// increment and method in history.csv, the same for the same seed, a stretched increment out of a
// rest-trained network's domain; bad --results and --domain refused; a ccx run of make-scene's hertz-slide
// (skipped without ccx).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app_runner.hpp"
#include "io/csv.hpp"
#include "io/network_model_file.hpp"
#include "io/plan_file.hpp"
#include "io/raw_configurations.hpp"
#include "search/local_search.hpp"
#include "study/history_fixture.hpp"

namespace contactnn::study {
namespace {

namespace fs = std::filesystem;

const fs::path kBin = CONTACTNN_BINARY_DIR;
const fs::path kScenes = CONTACTNN_EXAMPLE_SCENES_DIR;
const std::string kSmall =
    " --count 2000 --epochs 20 --long-epochs 0 --timing-queries 2000 --timing-repetitions 3 --threads 2 "
    "--quiet";

using contactnn::testing::read_file;
using contactnn::testing::run;

fs::path work_dir(const std::string& name) {
  const fs::path d =
      fs::path(::testing::TempDir()) / ("contactnn_scene_study_" + name + "." + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A CSV file as rows of name -> field.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  const auto split = [](const std::string& text) {
    std::vector<std::string> fields;
    std::stringstream s(text);
    std::string f;
    while (std::getline(s, f, ',')) fields.push_back(f);
    if (!text.empty() && text.back() == ',') fields.emplace_back();
    return fields;
  };
  std::getline(in, line);
  header = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Runs the study into `dir`; the plan it wrote.
io::ScenePlan study(const std::string& arguments, const fs::path& dir) {
  const std::string command = (kBin / "apps/scene-study/scene-study").string() + " " + arguments +
                              " --output '" + dir.string() + "'" + kSmall;
  const int code = run(command, dir.parent_path() / (dir.filename().string() + ".log"));
  EXPECT_EQ(code, 0) << command << "\n" << read_file(dir.parent_path() / (dir.filename().string() + ".log"));
  return io::read_plan(dir / "plan.toml");
}

/// evaluate-net --plan on the study's pairs; the output rows.
std::vector<std::map<std::string, std::string>> apply_plan(const fs::path& dir) {
  const fs::path out = dir / "plan-predictions.csv";
  const std::string command = (kBin / "apps/evaluate-net/evaluate-net").string() + " --plan '" +
                              (dir / "plan.toml").string() + "' --input '" + (dir / "pairs.csv").string() +
                              "' --output '" + out.string() + "'";
  EXPECT_EQ(run(command, dir / "evaluate-net.log"), 0) << read_file(dir / "evaluate-net.log");
  return read_csv(out);
}

/// Checks shared by every study: the pairs' locations as the report counts them; evaluate-net --plan gives
/// what the plan's method gives through lib/search; the plan's method meets the target on the face pairs; no
/// measured method reaches the target faster.
void check_study(const fs::path& dir, const io::ScenePlan& plan) {
  const auto pairs = read_csv(dir / "pairs.csv");
  ASSERT_FALSE(pairs.empty());
  std::map<std::string, long> locations;
  for (const auto& r : pairs) ++locations[r.at("location")];
  const std::string report = read_file(dir / "report.md");
  EXPECT_NE(report.find("inside a face for " + std::to_string(locations["face"]) + ", on an edge for " +
                        std::to_string(locations["edge"]) + ", at a vertex for " +
                        std::to_string(locations["vertex"])),
            std::string::npos)
      << report.substr(0, 2000);

  // evaluate-net --plan against the plan's method run here, in one batch, on the same rows (their raw columns
  // as read; a pairs row without a segment is not a query).
  const auto predicted = apply_plan(dir);
  ASSERT_EQ(predicted.size(), pairs.size());
  std::unique_ptr<search::NetworkModel> network;
  const fs::path network_file = plan_network_path(plan, dir / "plan.toml");
  if (!network_file.empty()) network = io::read_network_model(network_file);
  const search::LocalSearch search(plan.surface, search::Method::parse(plan.method), {}, network.get());
  io::RawConfigurationReader reader(dir / "pairs.csv", plan.surface);
  io::RawChunk chunk;
  std::vector<double> raw;
  std::vector<std::uint8_t> no_segment;
  while (reader.next_chunk(chunk, 1000)) {
    for (std::size_t i = 0; i < chunk.size(); ++i) {
      no_segment.push_back(chunk.no_segment[i]);
      for (const auto& n : chunk.configs[i].nodes) raw.insert(raw.end(), {n.x(), n.y(), n.z()});
      raw.insert(raw.end(),
                 {chunk.configs[i].slave.x(), chunk.configs[i].slave.y(), chunk.configs[i].slave.z()});
      if (plan.surface == SurfaceKind::kGregory) {
        for (const auto& n : chunk.configs[i].normals) raw.insert(raw.end(), {n.x(), n.y(), n.z()});
      }
    }
  }
  ASSERT_EQ(no_segment.size(), pairs.size());
  std::vector<double> param(2 * pairs.size());
  std::vector<Status> status(pairs.size());
  search.run(pairs.size(), raw.data(),
             search::Results<double>{param.data(), nullptr, status.data(), nullptr});
  const auto names = coordinate_names(plan.surface);
  double sum[2] = {0.0, 0.0};
  long face_rows = 0, face_failures = 0;
  for (std::size_t row = 0; row < pairs.size(); ++row) {
    const auto& out = predicted[row];
    if (no_segment[row] != 0) {
      EXPECT_EQ(out.at("status"), "no_segment") << "row " << row;
      continue;
    }
    const Status s = status[row];
    const double* p = &param[2 * row];
    EXPECT_EQ(out.at("status"), std::string(to_string(s))) << "row " << row;
    const bool has_value = s == Status::kOk || s == Status::kOutside || s == Status::kOutOfDomain;
    if (has_value) {
      EXPECT_EQ(out.at(std::string(names[0])), io::format_double(p[0])) << "row " << row;
      EXPECT_EQ(out.at(std::string(names[1])), io::format_double(p[1])) << "row " << row;
    }
    if (pairs[row].at("location") != "face") continue;
    ++face_rows;
    if (!has_value) {
      ++face_failures;
      continue;
    }
    sum[0] += std::abs(p[0] - std::stod(pairs[row].at(std::string(names[0]))));
    sum[1] += std::abs(p[1] - std::stod(pairs[row].at(std::string(names[1]))));
  }
  if (face_rows > 0) {
    EXPECT_EQ(face_failures, 0);
    EXPECT_LE(std::max(sum[0], sum[1]) / static_cast<double>(face_rows), plan.target)
        << plan.method << " on the " << face_rows << " face pairs";
  }

  // The plan's own measurement reaches margin x target, and no method reaching it was faster.
  const auto chosen =
      std::find_if(plan.measurements.begin(), plan.measurements.end(), [&](const io::PlanMeasurement& m) {
        return m.method == plan.method || m.method.rfind(plan.method + "[", 0) == 0;
      });
  ASSERT_NE(chosen, plan.measurements.end());
  EXPECT_TRUE(plan.reached);
  EXPECT_LE(chosen->effective_mean, plan.margin * plan.target);
  for (const io::PlanMeasurement& m : plan.measurements) {
    EXPECT_EQ(m.reaches_target, m.effective_mean <= plan.margin * plan.target) << m.method;
    if (m.reaches_target) {
      EXPECT_GE(m.batched_ns, chosen->batched_ns) << m.method << " is faster than " << chosen->method;
    }
  }
}

TEST(SceneStudyApp, FlatSceneGetsAPlanWithoutNetwork) {
  const fs::path dir = work_dir("flat") / "study";
  const io::ScenePlan plan =
      study("--scene '" + (kScenes / "flat.inp").string() + "' --pair 0 --surface bilinear", dir);
  EXPECT_EQ(plan.surface, SurfaceKind::kBilinear);
  EXPECT_TRUE(plan.network.empty());
  EXPECT_FALSE(search::Method::parse(plan.method).needs_network()) << plan.method;
  EXPECT_FALSE(fs::exists(dir / "network.h5"));
  EXPECT_GE(plan.measurements.size(), 5u);
  check_study(dir, plan);
}

TEST(SceneStudyApp, NetworkPlanIsWhatEvaluateNetApplies) {
  // Only the closed form beside the scene network's hybrid: the network's method wins (the closed form of the
  // corner facet is far from the Gregory patch on the curved cap).
  const fs::path dir = work_dir("hertz") / "study";
  const io::ScenePlan plan = study("--scene '" + (kScenes / "hertz.inp").string() +
                                       "' --pair 0 --surface gregory --methods closed_form --network-methods "
                                       "network+newton:2 --sizes 16 --train-networks always",
                                   dir);
  EXPECT_EQ(plan.surface, SurfaceKind::kGregory);
  EXPECT_EQ(plan.method, "network+newton:2");
  EXPECT_EQ(plan.network, "network.h5");
  EXPECT_TRUE(fs::exists(dir / "network.h5"));
  check_study(dir, plan);
  // A rerun whose plan has no network removes the old network file.
  const io::ScenePlan again = study("--scene '" + (kScenes / "hertz.inp").string() +
                                        "' --pair 0 --surface gregory "
                                        "--train-networks never",
                                    dir);
  EXPECT_TRUE(again.network.empty());
  EXPECT_FALSE(fs::exists(dir / "network.h5"));
}

TEST(SceneStudyApp, MalformedPlanIsRefusedNamingFileLineAndKey) {
  const fs::path dir = work_dir("malformed") / "study";
  (void)study(
      "--scene '" + (kScenes / "flat.inp").string() + "' --pair 1 --surface gregory --train-networks never",
      dir);
  const std::string text = read_file(dir / "plan.toml");
  const auto line_of = [&](const std::string& key) {
    const std::size_t at = text.find("\n" + key + " = ");
    return 2 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  };
  const auto refused = [&](const std::string& name, const std::string& content, const std::string& says) {
    const fs::path plan = dir / name;
    std::ofstream(plan) << content;
    const fs::path out = dir / (name + ".csv");
    const std::string command = (kBin / "apps/evaluate-net/evaluate-net").string() + " --plan '" +
                                plan.string() + "' --input '" + (dir / "pairs.csv").string() +
                                "' --output '" + out.string() + "'";
    EXPECT_EQ(run(command, dir / (name + ".log")), 3) << name;
    const std::string log = read_file(dir / (name + ".log"));
    EXPECT_NE(log.find("error: '" + plan.string() + says), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(out)) << "an output was left by a refused run";
  };
  // An unknown key, right after the method.
  std::string unknown = text;
  unknown.insert(text.find("\nmethod = ") + 1, "colour = \"blue\"\n");
  refused("unknown-key.toml", unknown,
          "':" + std::to_string(line_of("method")) + ": unknown key 'colour' in [plan]");
  // A missing field: no method.
  std::string missing = text;
  const std::size_t at = text.find("\nmethod = ") + 1;
  missing.erase(at, text.find('\n', at) - at + 1);
  refused("missing-field.toml", missing, "':5: [plan] has no key 'method' (required)");
}

TEST(SceneStudyApp, ConfigSectionIsStrict) {
  // [scene-study] sets the study's options as its flags do; an unknown key names the file, the line and the
  // key.
  const fs::path dir = work_dir("config");
  std::ofstream(dir / "good.toml") << "[scene-study]\ncount = 2000\nepochs = 20\nlong-epochs = 0\n"
                                      "train-networks = \"never\"\ntiming-queries = 2000\n";
  const std::string study_app = (kBin / "apps/scene-study/scene-study").string();
  const std::string scene =
      " --scene '" + (kScenes / "flat.inp").string() + "' --pair 1 --surface bilinear --quiet";
  ASSERT_EQ(run(study_app + " --config '" + (dir / "good.toml").string() + "'" + scene + " --output '" +
                    (dir / "good").string() + "'",
                dir / "good.log"),
            0)
      << read_file(dir / "good.log");
  const std::string effective = read_file(dir / "good" / "scene-study.config.toml");
  EXPECT_NE(effective.find("count=2000"), std::string::npos) << effective;
  EXPECT_NE(effective.find("train-networks=\"never\""), std::string::npos) << effective;
  std::ofstream(dir / "bad.toml") << "[scene-study]\ncount = 2000\nepoch = 20\n";
  EXPECT_EQ(run(study_app + " --config '" + (dir / "bad.toml").string() + "'" + scene + " --output '" +
                    (dir / "bad").string() + "'",
                dir / "bad.log"),
            2);
  const std::string log = read_file(dir / "bad.log");
  EXPECT_NE(log.find("line 3"), std::string::npos) << log;
  EXPECT_NE(log.find("unknown key 'epoch' in [scene-study]"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "bad" / "plan.toml"));
}

// --------------------------------------------------------------------------------- --results (issue 29)

/// The two blocks of study/history_fixture.hpp in `dir`: the deck and its 2-increment .frd.
void write_two_blocks(const fs::path& dir) {
  std::ofstream(dir / "two-blocks.inp") << fixture::kTwoBlocksDeck;
  std::ofstream(dir / "two-blocks.frd") << fixture::two_blocks_frd();
}

std::string study_command(const fs::path& deck, const std::string& arguments, const fs::path& out) {
  return (kBin / "apps/scene-study/scene-study").string() + " --scene '" + deck.string() +
         "' --surface bilinear --output '" + out.string() + "' " + arguments + kSmall;
}

TEST(SceneStudyApp, ResultsAndDomainOptionsAreChecked) {
  const fs::path dir = work_dir("history-options");
  write_two_blocks(dir);
  const fs::path deck = dir / "two-blocks.inp";
  const auto refused = [&](const std::string& name, const std::string& arguments, int code,
                           const std::string& expected) {
    const fs::path log = dir / (name + ".log");
    EXPECT_EQ(run(study_command(deck, arguments, dir / name), log), code) << arguments << "\n"
                                                                          << read_file(log);
    EXPECT_NE(read_file(log).find(expected), std::string::npos) << arguments << "\n" << read_file(log);
    EXPECT_FALSE(fs::exists(dir / name / "plan.toml")) << arguments;
  };
  // A results file that does not exist: exit 2 naming it.
  refused("missing", "--results '" + (dir / "no-such-run.frd").string() + "'", 2,
          (dir / "no-such-run.frd").string());
  // --domain: rest, history or auto.
  refused("bad-domain", "--domain union --results '" + (dir / "two-blocks.frd").string() + "'", 2,
          "--domain");
  refused("history-alone", "--domain history", 2, "--domain history");
  refused("bad-capture-pairs", "--capture-pairs nearest", 2, "--capture-pairs");
  // The [scene-study] key too.
  std::ofstream(dir / "bad.toml") << "[scene-study]\ndomain = \"everything\"\n";
  refused("bad-config", "--config '" + (dir / "bad.toml").string() + "'", 2, "domain");
  // A results file of another deck (its node block lacks the slave block's nodes): exit 3 naming it.
  const std::vector<long> nodes(fixture::kTwoBlocksNodes.begin(), fixture::kTwoBlocksNodes.begin() + 8);
  const auto all = fixture::two_blocks_coordinates();
  std::ofstream(dir / "other.frd") << fixture::frd_text(nodes, {all.begin(), all.begin() + 8},
                                                        {fixture::Displacements(8, {0.0, 0.0, 0.0})});
  refused("other", "--results '" + (dir / "other.frd").string() + "'", 3, (dir / "other.frd").string());
}

TEST(SceneStudyApp, JudgesEveryIncrementOfAHistory) {
  const fs::path dir = work_dir("history");
  write_two_blocks(dir);
  const fs::path out = dir / "study";
  const std::string command = study_command(
      dir / "two-blocks.inp",
      "--results '" + (dir / "two-blocks.frd").string() + "' --train-networks always --sizes 4,8", out);
  ASSERT_EQ(run(command, dir / "study.log"), 0) << command << "\n" << read_file(dir / "study.log");
  // history.csv: each scene network tried alone and the plan's method, one row per increment.
  const std::string csv_text = read_file(out / "history.csv");
  const auto rows = read_csv(out / "history.csv");
  std::map<std::string, std::vector<std::string>> increments;
  for (const auto& r : rows) {
    increments[r.at("method")].push_back(r.at("increment"));
    EXPECT_EQ(r.at("domain"), "history");  // the default with --results
    EXPECT_EQ(r.at("pairs"), "4");
    EXPECT_TRUE(std::isfinite(std::stod(r.at("mean_abs_xi"))) &&
                std::isfinite(std::stod(r.at("mean_abs_eta"))));
  }
  EXPECT_GE(increments.size(), 2u);
  EXPECT_EQ(increments.count("network[8-4-2]"), 1u);
  for (const auto& [method, list] : increments)
    EXPECT_EQ(list, (std::vector<std::string>{"1", "2"})) << method;
  const std::string report = read_file(out / "report.md");
  EXPECT_NE(report.find("## The history: 2 increments"), std::string::npos) << report;
  EXPECT_NE(report.find("drawn from the whole history: the deck and its 2 increments"), std::string::npos);
  EXPECT_NE(read_file(out / "report.json").find("\"history\": {"), std::string::npos);
  // The same study on the rest state alone: the stretched increment lies outside the networks' domain.
  const std::string rest = study_command(dir / "two-blocks.inp",
                                         "--results '" + (dir / "two-blocks.frd").string() +
                                             "' --domain rest --train-networks always --sizes 4,8",
                                         dir / "rest");
  ASSERT_EQ(run(rest, dir / "rest.log"), 0) << rest << "\n" << read_file(dir / "rest.log");
  int stretched = 0;
  for (const auto& r : read_csv(dir / "rest" / "history.csv")) {
    EXPECT_EQ(r.at("domain"), "rest");
    if (r.at("method") == "network[8-4-2]" && r.at("increment") == "2") {
      ++stretched;
      EXPECT_EQ(r.at("out_of_domain"), "4");
      EXPECT_EQ(r.at("out_of_domain_fraction"), "1");
      EXPECT_EQ(r.at("meets_target"), "false");
    }
  }
  EXPECT_EQ(stretched, 1);
  // Deterministic for a seed: the same history.csv again.
  ASSERT_EQ(run(command, dir / "again.log"), 0) << read_file(dir / "again.log");
  EXPECT_EQ(read_file(out / "history.csv"), csv_text);
  // Without --results an earlier run's history.csv is removed.
  ASSERT_EQ(run(study_command(dir / "two-blocks.inp", "--train-networks never", out), dir / "again.log"), 0)
      << read_file(dir / "again.log");
  EXPECT_FALSE(fs::exists(out / "history.csv"));
}

TEST(SceneStudyApp, HistoryOfACalculixRun) {
  // scripts/make-scene hertz-slide, small, run by ccx: a row per increment of the .frd for every method.
  if (std::system("command -v ccx > /dev/null 2>&1") != 0) GTEST_SKIP() << "ccx (CalculiX) is not installed";
  const fs::path dir = work_dir("calculix");
  const std::string make = "python3 '" + (fs::path(CONTACTNN_SOURCE_DIR) / "scripts/make-scene").string() +
                           "' hertz-slide --elements 4 --increments 2 --output '" + dir.string() + "'";
  ASSERT_EQ(run(make, dir / "make-scene.log"), 0) << read_file(dir / "make-scene.log");
  ASSERT_EQ(run("cd '" + dir.string() + "' && ccx -i hertz-slide", dir / "ccx.log"), 0)
      << read_file(dir / "ccx.log");
  const std::string command = study_command(
      dir / "hertz-slide.inp",
      "--results '" + (dir / "hertz-slide.frd").string() + "' --train-networks always --sizes 4",
      dir / "study");
  ASSERT_EQ(run(command, dir / "study.log"), 0) << command << "\n" << read_file(dir / "study.log");
  const auto rows = read_csv(dir / "study" / "history.csv");
  std::map<std::string, int> per_method;
  for (const auto& r : rows) {
    ++per_method[r.at("method")];
    EXPECT_GT(std::stol(r.at("pairs")), 0) << r.at("method") << " increment " << r.at("increment");
  }
  ASSERT_FALSE(per_method.empty());
  for (const auto& [method, n] : per_method)
    EXPECT_EQ(n, 7) << method;  // 5 increments of the press, 2 of the slide
}

}  // namespace
}  // namespace contactnn::study
