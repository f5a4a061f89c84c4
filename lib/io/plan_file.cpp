#include "io/plan_file.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/json_text.hpp"
#include "search/method.hpp"

namespace contactnn::io {

namespace {

using Keys = std::vector<std::string>;

const Keys kPlanKeys = {"schema_version", "surface", "method", "network", "target", "margin", "reached"};
const Keys kDomainKeys = {"deck",
                          "pair",
                          "deformation",
                          "capture",
                          "normal_tilt_tangent",
                          "boundary_fraction",
                          "heldout_count",
                          "heldout_seed",
                          "segment_test",
                          "states",
                          "results"};
const Keys kMeasurementKeys = {"method",   "mean_abs",   "effective_mean", "max_abs",
                               "failures", "batched_ns", "reaches_target"};

std::string join(const Keys& keys) {
  std::string out;
  for (const std::string& k : keys) out += (out.empty() ? "" : ", ") + k;
  return out;
}

std::int64_t line_of(const toml::node& node) { return static_cast<std::int64_t>(node.source().begin.line); }

/// One table of the plan, read key by key: every message names the file, the line and the key.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string name, const std::string& source, const Keys& allowed)
      : table_(table), name_(std::move(name)), source_(source) {
    // Unknown keys first, in file order (toml++ keeps keys sorted).
    std::vector<std::pair<std::int64_t, std::string>> unknown;
    for (const auto& [key, node] : table) {
      if (std::find(allowed.begin(), allowed.end(), std::string(key.str())) == allowed.end()) {
        unknown.emplace_back(line_of(node), std::string(key.str()));
      }
    }
    if (!unknown.empty()) {
      const auto first = std::min_element(unknown.begin(), unknown.end());
      fail(first->first,
           "unknown key '" + first->second + "' in " + name_ + " (expected one of: " + join(allowed) + ")");
    }
  }

  [[noreturn]] void fail(std::int64_t line, const std::string& message) const {
    throw FormatError("'" + source_ + "':" + std::to_string(line) + ": " + message);
  }

  /// The node of `key`, or a FormatError when it is missing and required (nullptr when optional).
  const toml::node* node(const std::string& key, bool required = true) const {
    const toml::node* n = table_.get(key);
    if (n == nullptr && required) fail(line_of(table_), name_ + " has no key '" + key + "' (required)");
    return n;
  }

  std::string string(const std::string& key, bool required = true) const {
    const toml::node* n = node(key, required);
    if (n == nullptr) return {};
    if (!n->is_string()) fail(line_of(*n), "key '" + key + "' in " + name_ + ": expected a string");
    return std::string(n->as_string()->get());
  }

  std::int64_t integer(const std::string& key, std::int64_t lo, bool required = true) const {
    const toml::node* n = node(key, required);
    if (n == nullptr) return lo;
    if (!n->is_integer()) fail(line_of(*n), "key '" + key + "' in " + name_ + ": expected an integer");
    const std::int64_t v = n->as_integer()->get();
    if (v < lo)
      fail(line_of(*n),
           "key '" + key + "' in " + name_ + ": " + std::to_string(v) + " is below " + std::to_string(lo));
    return v;
  }

  double real_of(const toml::node& n, const std::string& what) const {
    double v = 0.0;
    if (n.is_integer()) {
      v = static_cast<double>(n.as_integer()->get());
    } else if (n.is_floating_point()) {
      v = n.as_floating_point()->get();
    } else {
      fail(line_of(n), what + ": expected a number");
    }
    if (!std::isfinite(v) || v < 0.0) fail(line_of(n), what + ": expected a finite number >= 0");
    return v;
  }

  double real(const std::string& key, bool positive = false, bool required = true) const {
    const toml::node* n = node(key, required);
    if (n == nullptr) return 0.0;
    const double v = real_of(*n, "key '" + key + "' in " + name_);
    if (positive && !(v > 0.0))
      fail(line_of(*n), "key '" + key + "' in " + name_ + ": expected a number > 0");
    return v;
  }

  bool boolean(const std::string& key, bool required = true) const {
    const toml::node* n = node(key, required);
    if (n == nullptr) return false;
    if (!n->is_boolean()) fail(line_of(*n), "key '" + key + "' in " + name_ + ": expected true or false");
    return n->as_boolean()->get();
  }

  std::int64_t line(const std::string& key) const {
    const toml::node* n = table_.get(key);
    return n != nullptr ? line_of(*n) : line_of(table_);
  }

 private:
  const toml::table& table_;
  std::string name_;
  const std::string& source_;
};

PlanMeasurement read_measurement(const toml::table& table, std::size_t index, const std::string& source) {
  const TableReader r(table, "[[measurement]] " + std::to_string(index + 1), source, kMeasurementKeys);
  PlanMeasurement m;
  m.method = r.string("method");
  const toml::node* mean = r.node("mean_abs");
  const toml::array* values = mean->as_array();
  if (values == nullptr || values->size() != 2) {
    r.fail(line_of(*mean), "key 'mean_abs' in [[measurement]] " + std::to_string(index + 1) +
                               ": expected an array of 2 numbers");
  }
  for (std::size_t c = 0; c < 2; ++c) m.mean_abs[c] = r.real_of(*values->get(c), "key 'mean_abs'");
  m.effective_mean = r.real("effective_mean");
  m.max_abs = r.real("max_abs");
  m.failures = r.integer("failures", 0);
  m.batched_ns = r.real("batched_ns");
  m.reaches_target = r.boolean("reaches_target");
  return m;
}

/// A TOML basic string (the same text as a JSON string).
std::string quoted(const std::string& text) { return detail::json_string(text); }

/// A finite real as a TOML float that reads back to the same double.
std::string real_text(double v) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, std::isfinite(v),
                       "a scene plan holds finite numbers only, got " << v);
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v + 0.0);
  std::string s = buffer;
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

void check_method(const ScenePlan& plan, const std::function<void(const std::string&)>& fail) {
  search::Method method;
  try {
    method = search::Method::parse(plan.method);
  } catch (const InvalidArgument& e) {
    fail(std::string("key 'method' in [plan]: ") + e.what());
  }
  if (method.needs_network() && plan.network.empty()) {
    fail("key 'network' in [plan]: method '" + plan.method + "' needs a network file, the plan names none");
  }
  if (!method.needs_network() && !plan.network.empty()) {
    fail("key 'network' in [plan]: method '" + plan.method + "' uses no network, the plan names '" +
         plan.network + "'");
  }
}

}  // namespace

ScenePlan parse_plan(const std::string& text, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw FormatError("'" + source + "':" + std::to_string(e.source().begin.line) +
                      ": not valid TOML: " + std::string(e.description()));
  }
  const auto fail = [&](std::int64_t line, const std::string& message) {
    throw FormatError("'" + source + "':" + std::to_string(line) + ": " + message);
  };
  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (name == "plan" || name == "domain") {
      if (!node.is_table()) fail(line_of(node), "'" + name + "' must be a table ([" + name + "])");
    } else if (name == "measurement") {
      if (!node.is_array_of_tables())
        fail(line_of(node), "'measurement' must be an array of tables ([[measurement]])");
    } else {
      fail(line_of(node), (node.is_table() ? "unknown table [" + name + "]" : "unknown key '" + name + "'") +
                              " (expected [plan], [domain] and [[measurement]])");
    }
  }
  const toml::table* plan_table = root["plan"].as_table();
  const toml::table* domain_table = root["domain"].as_table();
  if (plan_table == nullptr) fail(1, "no [plan] table (required)");
  if (domain_table == nullptr) fail(1, "no [domain] table (required)");

  ScenePlan plan;
  const TableReader p(*plan_table, "[plan]", source, kPlanKeys);
  const std::int64_t version = p.integer("schema_version", 1);
  if (version != kPlanSchemaVersion) {
    p.fail(p.line("schema_version"), "key 'schema_version' in [plan]: " + std::to_string(version) +
                                         ", this version reads " + std::to_string(kPlanSchemaVersion));
  }
  const std::string surface = p.string("surface");
  try {
    plan.surface = surface_from_string(surface);
  } catch (const InvalidArgument& e) {
    p.fail(p.line("surface"), std::string("key 'surface' in [plan]: ") + e.what());
  }
  plan.method = p.string("method");
  plan.network = p.string("network");
  plan.target = p.real("target", true);
  plan.margin = p.real("margin", true);
  plan.reached = p.boolean("reached");
  check_method(plan, [&](const std::string& message) {
    p.fail(p.line(message.find("'network'") != std::string::npos ? "network" : "method"), message);
  });

  const TableReader d(*domain_table, "[domain]", source, kDomainKeys);
  plan.domain.deck = d.string("deck");
  plan.domain.pair = d.integer("pair", 0);
  plan.domain.deformation = d.real("deformation");
  plan.domain.capture = d.real("capture", true);
  plan.domain.normal_tilt_tangent = d.real("normal_tilt_tangent");
  plan.domain.boundary_fraction = d.real("boundary_fraction");
  plan.domain.heldout_count = d.integer("heldout_count", 1);
  plan.domain.heldout_seed = d.integer("heldout_seed", 0);
  // Optional (plans written before they existed: the rest state, the test on).
  plan.domain.segment_test = d.node("segment_test", false) == nullptr || d.boolean("segment_test");
  plan.domain.states = d.node("states", false) == nullptr ? std::string("rest") : d.string("states");
  if (plan.domain.states != "rest" && plan.domain.states != "history") {
    d.fail(d.line("states"), "key 'states' in [domain]: '" + quote_text(plan.domain.states) +
                                 "', expected \"rest\" or \"history\"");
  }
  plan.domain.results = d.string("results", false);

  if (const toml::array* measurements = root["measurement"].as_array()) {
    for (std::size_t i = 0; i < measurements->size(); ++i) {
      plan.measurements.push_back(read_measurement(*measurements->get(i)->as_table(), i, source));
    }
  }
  return plan;
}

ScenePlan read_plan(const std::filesystem::path& path) {
  // A directory opens as a stream on Linux and reads as nothing: it is a plan that cannot be read (IoError,
  // as contactnn.h says and as a network file that is a directory is), not a malformed one.
  std::error_code ec;
  CONTACTNN_REQUIRE_AS(IoError, !std::filesystem::is_directory(path, ec),
                       "cannot read the scene plan '" << path.string() << "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  CONTACTNN_REQUIRE_AS(IoError, in.good(), "cannot open the scene plan '" << path.string() << "'");
  std::ostringstream text;
  text << in.rdbuf();
  CONTACTNN_REQUIRE_AS(IoError, !in.bad(), "cannot read the scene plan '" << path.string() << "'");
  return parse_plan(text.str(), path.string());
}

std::string plan_to_toml(const ScenePlan& plan) {
  check_method(plan, [](const std::string& message) { throw InvalidArgument("scene plan: " + message); });
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, plan.target > 0.0 && plan.margin > 0.0,
      "scene plan: target " << plan.target << " and margin " << plan.margin << " must be > 0");
  std::ostringstream out;
  out << "# contactnn scene plan (SPEC 7), written by scene-study: the local-search method chosen for one "
         "contact\n"
         "# pair, the fastest of those measured whose held-out mean |error| reaches margin x target on the "
         "scene's\n"
         "# domain. Load it with evaluate-net --plan, contactnn_search_create_from_plan (C) or\n"
         "# contactnn_create_from_plan (Fortran). Format: lib/io/plan_file.hpp.\n"
      << "[plan]\n"
      << "schema_version = " << kPlanSchemaVersion << "\n"
      << "surface = " << quoted(std::string(to_string(plan.surface))) << "\n"
      << "method = " << quoted(plan.method) << "\n"
      << "network = " << quoted(plan.network) << "  # relative to this file; \"\": the method needs none\n"
      << "target = " << real_text(plan.target) << "\n"
      << "margin = " << real_text(plan.margin) << "\n"
      << "reached = " << (plan.reached ? "true" : "false") << "\n\n"
      << "[domain]\n"
      << "deck = " << quoted(plan.domain.deck) << "\n"
      << "pair = " << plan.domain.pair << "\n"
      << "deformation = " << real_text(plan.domain.deformation) << "\n"
      << "capture = " << real_text(plan.domain.capture) << "\n"
      << "normal_tilt_tangent = " << real_text(plan.domain.normal_tilt_tangent) << "\n"
      << "boundary_fraction = " << real_text(plan.domain.boundary_fraction) << "\n"
      << "heldout_count = " << plan.domain.heldout_count << "\n"
      << "heldout_seed = " << plan.domain.heldout_seed << "\n"
      << "segment_test = " << (plan.domain.segment_test ? "true" : "false") << "\n"
      << "states = " << quoted(plan.domain.states) << "\n"
      << "results = " << quoted(plan.domain.results) << "\n";
  for (const PlanMeasurement& m : plan.measurements) {
    out << "\n[[measurement]]\n"
        << "method = " << quoted(m.method) << "\n"
        << "mean_abs = [" << real_text(m.mean_abs[0]) << ", " << real_text(m.mean_abs[1]) << "]\n"
        << "effective_mean = " << real_text(m.effective_mean) << "\n"
        << "max_abs = " << real_text(m.max_abs) << "\n"
        << "failures = " << m.failures << "\n"
        << "batched_ns = " << real_text(m.batched_ns) << "\n"
        << "reaches_target = " << (m.reaches_target ? "true" : "false") << "\n";
  }
  return out.str();
}

std::filesystem::path plan_network_path(const ScenePlan& plan, const std::filesystem::path& plan_path) {
  if (plan.network.empty()) return {};
  const std::filesystem::path network(plan.network);
  return network.is_absolute() ? network : plan_path.parent_path() / network;
}

}  // namespace contactnn::io
