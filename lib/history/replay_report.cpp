// replay's report (replay.hpp, write_replay_report): increments.csv, report.md and the plots, each written
// by a step of its own from the increments' rows and their totals.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>

#include "core/number_text.hpp"
#include "eval/svg_plot.hpp"
#include "history/replay.hpp"
#include "io/csv.hpp"

namespace contactnn::history {

namespace {

/// Totals over the increments of one method's row (by position: every increment has the same methods).
struct MethodTotal {
  std::string method;
  long queries = 0;
  double ns_sum = 0.0;     ///< sum of ns_per_query x queries
  double error_sum = 0.0;  ///< sum of mean_error x judged
  long judged = 0;
  double max_error = 0.0;
  long failures = 0;
};

/// The sums over every increment that the report's summary gives.
struct Totals {
  long slaves = 0, found = 0, changed = 0, differences = 0, fresh_lists = 0, tracked = 0, contacts = 0,
       contacts_found = 0;
  double scene_ns = 0.0, fresh_ns = 0.0, tracked_ns = 0.0, calculix_largest = 0.0;
  double fresh_reference_ns = 0.0, tracked_reference_ns = 0.0;
  long reference_faces = 0, reference_differences = 0;
  std::array<long, 3> locations{};
  std::vector<MethodTotal> methods;
  bool calculix = false;
};

void add_methods(const IncrementRow& r, std::vector<MethodTotal>& totals) {
  if (totals.empty()) {
    for (const MethodRow& m : r.methods) totals.push_back({m.method});
  }
  for (std::size_t j = 0; j < r.methods.size() && j < totals.size(); ++j) {
    const MethodRow& m = r.methods[j];
    MethodTotal& t = totals[j];
    t.queries += m.queries;
    t.ns_sum += m.ns_per_query * static_cast<double>(m.queries);
    const long judged = m.queries - m.failures;
    t.error_sum += m.mean_error * static_cast<double>(judged);
    t.judged += judged;
    t.max_error = std::max(t.max_error, m.max_error);
    t.failures += m.failures;
  }
}

Totals totals_of(const std::vector<IncrementRow>& rows) {
  Totals t;
  for (const IncrementRow& r : rows) {
    const auto weight = static_cast<double>(r.slaves);
    t.slaves += r.slaves;
    t.found += r.found;
    t.changed += r.faces_changed;
    t.differences += r.tracking_differences;
    t.fresh_lists += r.tracking.fresh;
    t.tracked += r.tracking.tracked;
    t.scene_ns += r.ns_scene * weight;
    t.fresh_ns += r.ns_fresh * weight;
    t.tracked_ns += r.ns_tracked * weight;
    t.fresh_reference_ns += r.ns_fresh_reference * weight;
    t.tracked_reference_ns += r.ns_tracked_reference * weight;
    t.reference_faces += r.reference_faces;
    t.reference_differences += r.reference_differences;
    for (std::size_t k = 0; k < 3; ++k) t.locations[k] += r.locations[k];
    if (r.calculix_contacts >= 0) {
      t.calculix = true;
      t.contacts += r.calculix_contacts;
      t.contacts_found += r.calculix_found;
      t.calculix_largest = std::max(t.calculix_largest, r.calculix_largest_difference);
    }
    add_methods(r, t.methods);
  }
  return t;
}

double per(double total_ns, long count) { return count > 0 ? total_ns / static_cast<double>(count) : 0.0; }

/// increments.csv: one row per increment, one column group per method, then the plan's (with one).
std::string increments_csv(const ReplayOptions& options, const std::vector<IncrementRow>& rows) {
  std::string csv =
      "increment,step,time,slaves,found,face,edge,vertex,faces_changed,tracking_differences,fresh_lists,"
      "tracked,ns_scene,ns_fresh,ns_tracked,calculix_contacts,calculix_found,calculix_largest_difference,"
      "reference_faces,ns_fresh_reference,ns_tracked_reference,reference_differences";
  if (!rows.empty()) {
    for (const MethodRow& m : rows.front().methods) {
      csv += "," + m.method + ":queries," + m.method + ":ns," + m.method + ":mean_error," + m.method +
             ":max_error," + m.method + ":failures";
    }
  }
  const bool plan = options.plan != nullptr;
  if (plan) {
    csv +=
        ",plan:ns_fresh,plan:ns_tracked,plan:by_method,plan:fallbacks,plan:refused,plan:other_face,"
        "plan:mean_error,plan:max_error,plan:mean_distance,plan:max_distance,plan:target";
  }
  csv += "\n";
  for (const IncrementRow& r : rows) {
    csv += std::to_string(r.increment) + "," + std::to_string(r.step) + "," + fmt("%.9g", r.time) + "," +
           std::to_string(r.slaves) + "," + std::to_string(r.found) + "," + std::to_string(r.locations[0]) +
           "," + std::to_string(r.locations[1]) + "," + std::to_string(r.locations[2]) + "," +
           std::to_string(r.faces_changed) + "," + std::to_string(r.tracking_differences) + "," +
           std::to_string(r.tracking.fresh) + "," + std::to_string(r.tracking.tracked) + "," +
           fmt("%.1f", r.ns_scene) + "," + fmt("%.1f", r.ns_fresh) + "," + fmt("%.1f", r.ns_tracked) + "," +
           std::to_string(r.calculix_contacts) + "," + std::to_string(r.calculix_found) + "," +
           fmt("%.3g", r.calculix_largest_difference) + "," + std::to_string(r.reference_faces) + "," +
           fmt("%.1f", r.ns_fresh_reference) + "," + fmt("%.1f", r.ns_tracked_reference) + "," +
           std::to_string(r.reference_differences);
    for (const MethodRow& m : r.methods) {
      csv += "," + std::to_string(m.queries) + "," + fmt("%.1f", m.ns_per_query) + "," +
             fmt("%.3g", m.mean_error) + "," + fmt("%.3g", m.max_error) + "," + std::to_string(m.failures);
    }
    if (plan) {
      const PlanRow& p = r.plan;
      csv += "," + fmt("%.1f", p.ns_fresh) + "," + fmt("%.1f", p.ns_tracked) + "," +
             std::to_string(p.by_method) + "," + std::to_string(p.fallbacks) + "," +
             std::to_string(p.refused) + "," + std::to_string(p.other_face) + "," +
             fmt("%.3g", p.mean_error) + "," + fmt("%.3g", p.max_error) + "," + fmt("%.3g", p.mean_distance) +
             "," + fmt("%.3g", p.max_distance) + "," + fmt("%.3g", options.plan_target);
    }
    csv += "\n";
  }
  return csv;
}

/// report.md's summary: the surface search's phases, the narrow phase, tracking, CalculiX.
std::string summary_md(const std::string& title, const ReplayOptions& options,
                       const std::vector<IncrementRow>& rows, const Totals& t) {
  std::string md = "# Replay: " + eval::xml_escape(title) + "\n\n";
  md += std::to_string(rows.size()) + " increments, " + std::string(to_string(options.search.surface)) +
        " surface, " + std::to_string(options.threads) + " thread(s); timings are the fastest of " +
        std::to_string(options.repeats) +
        " runs of each call (tracking: as many trackers, each stepped through every increment).\n\n";
  md += "## Surface search per increment (ns per slave node, over all increments)\n\n";
  md += "| phase | ns per slave node | ratio to fresh |\n|---|---|---|\n";
  md += "| scene (nodes moved, normals) | " + fmt("%.0f", per(t.scene_ns, t.slaves)) + " | |\n";
  md += "| fresh surface search | " + fmt("%.0f", per(t.fresh_ns, t.slaves)) + " | 1 |\n";
  md += "| tracked surface search | " + fmt("%.0f", per(t.tracked_ns, t.slaves)) + " | " +
        fmt("%.3f", t.fresh_ns > 0 ? t.tracked_ns / t.fresh_ns : 0.0) + " |\n";
  if (t.fresh_reference_ns > 0.0 && t.fresh_ns > 0.0) {
    md += "| fresh, reference narrow phase (the search before the certificate) | " +
          fmt("%.0f", per(t.fresh_reference_ns, t.slaves)) + " | " +
          fmt("%.3f", t.fresh_reference_ns / t.fresh_ns) + " |\n";
    md += "| tracked, reference narrow phase | " + fmt("%.0f", per(t.tracked_reference_ns, t.slaves)) +
          " | " + fmt("%.3f", t.tracked_reference_ns / t.fresh_ns) + " |\n";
  }
  md += "\nNarrow phase: " + std::to_string(t.reference_faces) +
        " faces needed the reference (no certificate) over all slave node states";
  if (t.fresh_reference_ns > 0.0) {
    md += "; " + std::to_string(t.reference_differences) +
          " fresh answers differ from the reference search's (status, face, location; point or gap by more "
          "than 1e-10 of the face size)";
  }
  md += ".\n\n";
  md += "Tracking: " + std::to_string(t.differences) + " answers of " + std::to_string(t.slaves) +
        " differ from the fresh search's (face, point to 1e-12, gap); " + std::to_string(t.fresh_lists) +
        " node searches without a previous face, " + std::to_string(t.tracked) +
        " from their previous face (the grid's margin " + fmt("%g", options.tracking.grid_margin_relative) +
        " x the capture distance; the reference tracker's lists: " +
        fmt("%g", options.tracking.margin_relative) + "). Points found: " + std::to_string(t.found) +
        " (face " + std::to_string(t.locations[0]) + ", edge " + std::to_string(t.locations[1]) +
        ", vertex " + std::to_string(t.locations[2]) + "); " + std::to_string(t.changed) +
        " times a node moved to another face.\n\n";
  if (t.differences > 0) {
    md +=
        "The first tracked answers that differ (at most 5 per increment):\n\n| increment | slave node | "
        "fresh | tracked |\n|---|---|---|---|\n";
    for (const IncrementRow& r : rows) {
      for (const std::string& line : r.differences) md += line + "\n";
    }
    md += "\n";
  }
  if (rows.size() > 1) {
    double fresh_later = 0.0, tracked_later = 0.0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      fresh_later += rows[k].ns_fresh * static_cast<double>(rows[k].slaves);
      tracked_later += rows[k].ns_tracked * static_cast<double>(rows[k].slaves);
    }
    md +=
        "After the first increment (whose tracked search builds every list: a fresh search and more), "
        "tracked / fresh is " +
        fmt("%.3f", fresh_later > 0 ? tracked_later / fresh_later : 0.0) + ".\n\n";
  }
  if (t.calculix) {
    md += "CalculiX: " + std::to_string(t.contacts) + " contacts (COPEN < 0) of this pair's slave nodes, " +
          std::to_string(t.contacts_found) + " with a point; largest |gap - COPEN| " +
          fmt("%.3g", t.calculix_largest) + " (scripts/calculix-compare states the .frd's precision).\n\n";
  }
  return md;
}

/// report.md's table of the local-search methods over every increment.
std::string methods_md(const Totals& t) {
  std::string md = "## Local search on the pairs inside faces (all increments)\n\n";
  md +=
      "Cold methods on every point inside a segment face; start+newton:K from the previous increment's point "
      "on the nodes that keep their face. Error: max(|d xi|, |d eta|) against the surface search's point, "
      "local units.\n\n";
  md +=
      "| method | queries | ns per query | mean \\|error\\| | max \\|error\\| | failures "
      "|\n|---|---|---|---|---|---|\n";
  int smallest_warm = -1;
  for (const MethodTotal& m : t.methods) {
    const double mean = m.judged > 0 ? m.error_sum / static_cast<double>(m.judged) : 0.0;
    md += "| " + m.method + " | " + std::to_string(m.queries) + " | " +
          fmt("%.1f", per(m.ns_sum, m.queries)) + " | " + fmt("%.3g", mean) + " | " +
          fmt("%.3g", m.max_error) + " | " + std::to_string(m.failures) + " |\n";
    if (smallest_warm < 0 && m.method.rfind("start+newton:", 0) == 0 && m.queries > 0 && mean <= 1e-10 &&
        m.failures == 0) {
      smallest_warm = std::stoi(m.method.substr(13));
    }
  }
  md += "\nSmallest K for which start+newton:K reaches the surface search's points to 1e-10 (mean): " +
        (smallest_warm >= 0 ? std::to_string(smallest_warm) : std::string("none of those run")) + ".\n\n";
  return md;
}

/// report.md's section on the plan in the loop: per increment, its search's time beside the exact one's, and
/// its answers against the exact ones.
std::string plan_md(const ReplayOptions& options, const std::vector<IncrementRow>& rows) {
  if (options.plan == nullptr) return {};
  std::string md = "## The plan in the loop: " + options.plan_label + "\n\n";
  md += "The surface search with `" + options.plan->name() +
        "` on face interiors (a pair it refuses or puts outside the face takes the exact closest point), "
        "against the exact search's answers. Error: max(|d s|, |d t|) of the local coordinates where the "
        "method gave the point (one domain width on another face); distance: |P - P_exact| / face size. "
        "Target " +
        (options.plan_target > 0.0 ? fmt("%g", options.plan_target) : std::string("none")) + ".\n\n";
  md +=
      "| increment | ns fresh exact | ns fresh plan | ns tracked exact | ns tracked plan | by method | "
      "fallbacks | refused | other face | mean \\|error\\| | max \\|error\\| | max distance | target met "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  long refused = 0, missed = 0;
  for (const IncrementRow& r : rows) {
    const PlanRow& p = r.plan;
    const bool met = options.plan_target <= 0.0 || p.mean_error <= options.plan_target;
    refused += p.refused;
    missed += met ? 0 : 1;
    md += "| " + std::to_string(r.increment) + " | " + fmt("%.0f", r.ns_fresh) + " | " +
          fmt("%.0f", p.ns_fresh) + " | " + fmt("%.0f", r.ns_tracked) + " | " + fmt("%.0f", p.ns_tracked) +
          " | " + std::to_string(p.by_method) + " | " + std::to_string(p.fallbacks) + " | " +
          std::to_string(p.refused) + " | " + std::to_string(p.other_face) + " | " +
          fmt("%.3g", p.mean_error) + " | " + fmt("%.3g", p.max_error) + " | " + fmt("%.3g", p.max_distance) +
          " | " + (met ? "yes" : "no") + " |\n";
  }
  md += "\nPlan: " + std::to_string(refused) +
        " slave points refused over all increments; the target missed at " + std::to_string(missed) +
        " increment(s).\n\n";
  return md;
}

/// report.md's per-increment table.
std::string increments_md(const std::vector<IncrementRow>& rows, bool calculix) {
  std::string md =
      "## Per increment\n\n| increment | time | found | face / edge / vertex | faces changed | tracking "
      "differences | nodes without a previous face | ns fresh | ns tracked |" +
      std::string(calculix ? " CalculiX contacts / found / max \\|gap - COPEN\\| |" : "") +
      "\n|---|---|---|---|---|---|---|---|---|" + std::string(calculix ? "---|" : "") + "\n";
  for (const IncrementRow& r : rows) {
    md += "| " + std::to_string(r.increment) + " | " + fmt("%.6g", r.time) + " | " + std::to_string(r.found) +
          " | " + std::to_string(r.locations[0]) + " / " + std::to_string(r.locations[1]) + " / " +
          std::to_string(r.locations[2]) + " | " + std::to_string(r.faces_changed) + " | " +
          std::to_string(r.tracking_differences) + " | " + std::to_string(r.tracking.fresh) + " | " +
          fmt("%.0f", r.ns_fresh) + " | " + fmt("%.0f", r.ns_tracked) + " |";
    if (calculix) {
      md += r.calculix_contacts < 0
                ? std::string(" - |")
                : " " + std::to_string(r.calculix_contacts) + " / " + std::to_string(r.calculix_found) +
                      " / " + fmt("%.3g", r.calculix_largest_difference) + " |";
    }
    md += "\n";
  }
  md +=
      "\nPlots: [time per phase](time.svg), [error per method](error.svg), [contacts by "
      "location](locations.svg); the numbers: increments.csv.\n";
  return md;
}

/// time.svg, error.svg and locations.svg over the increments.
void write_plots(const std::filesystem::path& dir, const std::string& title,
                 const std::vector<IncrementRow>& rows, const Totals& t) {
  std::vector<double> x;
  for (const IncrementRow& r : rows) x.push_back(r.increment);
  const auto series = [&](auto value) {
    std::vector<double> y;
    for (const IncrementRow& r : rows) y.push_back(value(r));
    return y;
  };
  eval::LineSeries scene_series{"scene", series([](const IncrementRow& r) { return r.ns_scene; })};
  eval::LineSeries fresh_series{"fresh search", series([](const IncrementRow& r) { return r.ns_fresh; })};
  eval::LineSeries tracked_series{"tracked search",
                                  series([](const IncrementRow& r) { return r.ns_tracked; })};
  io::write_text_atomically(
      dir / "time.svg",
      eval::line_plot_svg(x, {scene_series, fresh_series, tracked_series},
                          {"Time per phase, " + title, "increment", "ns per slave node"}, true));
  std::vector<eval::LineSeries> errors;
  for (std::size_t j = 0; j < t.methods.size(); ++j) {
    errors.push_back({t.methods[j].method, series([&](const IncrementRow& r) {
                        return j < r.methods.size() ? r.methods[j].mean_error : 0.0;
                      })});
  }
  io::write_text_atomically(
      dir / "error.svg",
      eval::line_plot_svg(
          x, errors, {"Mean |error| per method, " + title, "increment", "mean |error| (local units)"}, true));
  io::write_text_atomically(
      dir / "locations.svg",
      eval::line_plot_svg(
          x,
          {{"face", series([](const IncrementRow& r) { return static_cast<double>(r.locations[0]); })},
           {"edge", series([](const IncrementRow& r) { return static_cast<double>(r.locations[1]); })},
           {"vertex", series([](const IncrementRow& r) { return static_cast<double>(r.locations[2]); })}},
          {"Contacts by location, " + title, "increment", "slave nodes"}, false));
}

}  // namespace

void write_replay_report(const std::string& directory, const std::string& title, const ReplayOptions& options,
                         const std::vector<IncrementRow>& rows) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path dir(directory);
  io::write_text_atomically(dir / "increments.csv", increments_csv(options, rows));
  const Totals totals = totals_of(rows);
  io::write_text_atomically(dir / "report.md", summary_md(title, options, rows, totals) + methods_md(totals) +
                                                   plan_md(options, rows) +
                                                   increments_md(rows, totals.calculix));
  write_plots(dir, title, rows, totals);
}

}  // namespace contactnn::history
