#include "history/replay.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "contact/scene.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "eval/svg_plot.hpp"
#include "io/csv.hpp"
#include "search/local_search.hpp"

namespace contactnn::history {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Faces, points (to 1e-12 of their magnitude) and gaps equal: the tracked search answered as the fresh one.
bool same_answer(const contact::NodeSegmentPair& a, const contact::NodeSegmentPair& b) {
  if (a.status != b.status) return false;
  if (a.status != contact::PairStatus::kFound) return true;
  const double tol = 1e-12 * (1.0 + a.point.norm());
  return a.segment == b.segment && (a.point - b.point).norm() <= tol &&
         std::abs(a.label.gap - b.label.gap) <= tol;
}

/// The same answer as the reference search's to 1e-10 of the face's size (its longest corner distance):
/// status, face and location, the point and the gap.
bool same_as_reference(const mesh::SurfaceMesh& master, const contact::NodeSegmentPair& a,
                       const contact::NodeSegmentPair& b) {
  if (a.status != b.status) return false;
  if (a.status != contact::PairStatus::kFound) return true;
  if (a.segment != b.segment || a.location != b.location) return false;
  double size = 0.0;
  for (const int i : master.face_corners(a.segment)) {
    for (const int j : master.face_corners(a.segment)) {
      size = std::max(size, (master.positions[static_cast<std::size_t>(i)] -
                             master.positions[static_cast<std::size_t>(j)])
                                .norm());
    }
  }
  const double tol = 1e-10 * size;
  return (a.point - b.point).norm() <= tol && std::abs(a.label.gap - b.label.gap) <= tol;
}

/// One answer as a report cell: status, or face, location, point and gap.
std::string answer_cell(const contact::NodeSegmentPair& p) {
  if (p.status != contact::PairStatus::kFound) return "no_segment";
  static constexpr const char* kWhere[] = {"face", "edge", "vertex"};
  char text[200];
  std::snprintf(text, sizeof text, "face %d (%s), P (%.17g, %.17g, %.17g), gap %.17g", p.segment,
                kWhere[static_cast<int>(p.location)], p.point.x(), p.point.y(), p.point.z(), p.label.gap);
  return text;
}

/// A node whose tracked answer differs from the fresh one, as a Markdown table row.
std::string difference_row(int increment, const contact::NodeSegmentPair& fresh,
                           const contact::NodeSegmentPair& tracked) {
  return "| " + std::to_string(increment) + " | " + std::to_string(fresh.slave_id) + " | " +
         answer_cell(fresh) + " | " + answer_cell(tracked) + " |";
}

/// The local-search queries of one increment: the found nodes whose point lies inside a quad4 segment face,
/// in the face's own node order (raw rows of SPEC 6), with the surface search's point as the reference.
struct Queries {
  std::vector<double> raw;  ///< count x 15 or 27
  std::vector<std::array<double, 2>> reference;
  std::vector<std::size_t> node;  ///< index of the slave node
};

Queries face_queries(const contact::Scene& scene, const std::vector<contact::NodeSegmentPair>& pairs,
                     SurfaceKind kind, const std::vector<char>* only) {
  Queries q;
  const bool gregory = kind == SurfaceKind::kGregory;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const contact::NodeSegmentPair& p = pairs[i];
    if (p.status != contact::PairStatus::kFound || p.location != Location::kFace) continue;
    // lib/search's methods are for the segments' quad4 surfaces (a C3D20 face is a quad8 for the search).
    if (static_cast<std::size_t>(p.segment) >= scene.master.segments.size()) continue;
    if (scene.master.face_type(p.segment) != mesh::FaceType::kQuad4) continue;
    if (only != nullptr && (*only)[i] == 0) continue;
    const auto& quad = scene.master.segments[static_cast<std::size_t>(p.segment)];
    for (int n : quad) {
      for (int k = 0; k < 3; ++k) q.raw.push_back(scene.master.positions[static_cast<std::size_t>(n)][k]);
    }
    for (int k = 0; k < 3; ++k) q.raw.push_back(scene.slave_positions[i][k]);
    if (gregory) {
      for (int n : quad) {
        for (int k = 0; k < 3; ++k) q.raw.push_back(scene.master_normals[static_cast<std::size_t>(n)][k]);
      }
    }
    q.reference.push_back(p.face_param);
    q.node.push_back(i);
  }
  return q;
}

/// One method on the queries: the fastest of `repeats` batched runs, its errors against the reference.
/// `starts` (warm methods) are copied into the parameters before every run.
MethodRow run_method(const std::string& name, SurfaceKind kind, const Queries& q,
                     const ReplayOptions& options, const std::vector<double>* starts) {
  MethodRow row;
  row.method = name;
  row.queries = static_cast<long>(q.reference.size());
  if (q.reference.empty()) return row;
  const search::Method method = search::Method::parse(name);
  const search::LocalSearch local(kind, method, {}, method.needs_network() ? options.network : nullptr);
  const std::size_t n = q.reference.size();
  std::vector<double> param(2 * n), gap(n);
  std::vector<Status> status(n);
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < std::max(options.repeats, 1); ++r) {
    if (starts != nullptr) param = *starts;
    const auto start = Clock::now();
    local.run<double>(n, q.raw.data(), {param.data(), gap.data(), status.data(), nullptr}, options.threads);
    best = std::min(best, seconds_since(start));
  }
  row.ns_per_query = 1e9 * best / static_cast<double>(n);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (status[i] != Status::kOk && status[i] != Status::kOutside) {
      ++row.failures;
      continue;
    }
    const double e =
        std::max(std::abs(param[2 * i] - q.reference[i][0]), std::abs(param[2 * i + 1] - q.reference[i][1]));
    sum += e;
    row.max_error = std::max(row.max_error, e);
  }
  const long judged = row.queries - row.failures;
  row.mean_error = judged > 0 ? sum / static_cast<double>(judged) : 0.0;
  return row;
}

}  // namespace

std::vector<IncrementRow> replay(mesh::ContactModel& model, const io::FrdResults& results,
                                 const ReplayOptions& options,
                                 const std::function<void(int, int)>& progress) {
  for (const std::string& m : options.methods) {
    const search::Method method = search::Method::parse(m);
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_network() || options.network != nullptr,
                         "method '" << m << "' needs a network (--weights)");
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_start(),
                         "method '" << m << "': warm starts are --warm_steps");
  }
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(std::max(options.threads, 1));
  contact::SurfaceTracker tracker(options.search, options.tracking);
  contact::SearchOptions reference_options = options.search;
  reference_options.narrow = contact::NarrowPhase::kReference;
  const bool beside = options.beside_reference && options.search.narrow != contact::NarrowPhase::kReference;
  contact::SurfaceTracker reference_tracker(reference_options, options.tracking);
  std::vector<IncrementRow> rows;
  std::vector<contact::NodeSegmentPair> previous, fresh, tracked, reference, reference_tracked;
  const int total = static_cast<int>(results.increments.size());
  for (int k = 0; k < total; ++k) {
    const io::FrdIncrement& increment = results.increments[static_cast<std::size_t>(k)];
    IncrementRow row;
    row.increment = increment.number;
    row.step = increment.step;
    row.time = increment.time;

    // 1. The state: nodes moved, the pair's faces, node normals and slave nodes.
    auto start = Clock::now();
    io::move_to_increment(model.mesh, results, static_cast<std::size_t>(k));
    const contact::Scene scene = contact::make_scene(model, options.pair);
    const double scene_seconds = seconds_since(start);
    const auto n = static_cast<long>(scene.slave_ids.size());
    row.slaves = n;
    const double per_node = n > 0 ? 1e9 / static_cast<double>(n) : 0.0;
    row.ns_scene = scene_seconds * per_node;

    // 2. The surface search, fresh (the fastest of `repeats`) and tracked (once: it keeps state).
    // Both searches write into buffers kept from one increment to the next, as an FE code's would.
    const int repeats = std::max(options.repeats, 1);
    const auto time_fresh = [&](const contact::SearchOptions& search,
                                std::vector<contact::NodeSegmentPair>& out) {
      double best = std::numeric_limits<double>::infinity();
      for (int r = 0; r < repeats; ++r) {
        start = Clock::now();
        contact::surface_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions,
                                search, out);
        best = std::min(best, seconds_since(start));
      }
      return best * per_node;
    };
    // Tracking keeps state: each timed run steps a copy of the tracker (the copy outside the time), the last
    // one goes on.
    const auto time_tracked = [&](contact::SurfaceTracker& kept_tracker,
                                  std::vector<contact::NodeSegmentPair>& out,
                                  contact::TrackingCounts* counts) {
      double best = std::numeric_limits<double>::infinity();
      for (int r = 0; r < repeats; ++r) {
        contact::SurfaceTracker trial = kept_tracker;
        start = Clock::now();
        trial.step(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, out, counts);
        best = std::min(best, seconds_since(start));
        if (r + 1 == repeats) kept_tracker = std::move(trial);
      }
      return best * per_node;
    };
    row.ns_fresh = time_fresh(options.search, fresh);
    row.ns_tracked = time_tracked(tracker, tracked, &row.tracking);
    for (const contact::NodeSegmentPair& p : fresh) row.reference_faces += p.reference_faces;
    if (beside) {
      // The search as it was, timed the same way beside this one; the fresh answers compared.
      row.ns_fresh_reference = time_fresh(reference_options, reference);
      row.ns_tracked_reference = time_tracked(reference_tracker, reference_tracked, nullptr);
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        if (!same_as_reference(scene.master, fresh[i], reference[i])) ++row.reference_differences;
      }
    }
    std::vector<char> kept(fresh.size(), 0);
    for (std::size_t i = 0; i < fresh.size(); ++i) {
      if (!same_answer(fresh[i], tracked[i])) {
        ++row.tracking_differences;
        if (row.differences.size() < 5)
          row.differences.push_back(difference_row(increment.number, fresh[i], tracked[i]));
      }
      if (fresh[i].status != contact::PairStatus::kFound) continue;
      ++row.found;
      ++row.locations[static_cast<std::size_t>(fresh[i].location)];
      if (previous.size() == fresh.size() && previous[i].status == contact::PairStatus::kFound) {
        if (previous[i].segment == fresh[i].segment) {
          kept[i] = 1;
        } else {
          ++row.faces_changed;
        }
      }
    }

    // 3. The local search of each method on the pairs inside segment faces; warm starts on the kept faces.
    const Queries all = face_queries(scene, fresh, options.search.surface, nullptr);
    for (const std::string& m : options.methods)
      row.methods.push_back(run_method(m, options.search.surface, all, options, nullptr));
    const Queries warm = face_queries(scene, fresh, options.search.surface, &kept);
    std::vector<double> starts;
    for (std::size_t j = 0; j < warm.node.size(); ++j) {
      starts.push_back(previous[warm.node[j]].face_param[0]);
      starts.push_back(previous[warm.node[j]].face_param[1]);
    }
    for (int steps : options.warm_steps) {
      row.methods.push_back(run_method("start+newton:" + std::to_string(steps), options.search.surface, warm,
                                       options, &starts));
    }

    // 4. CalculiX's own contact state: every slave node of this pair it reports in contact (COPEN < 0).
    if (increment.contact.empty()) {
      row.calculix_contacts = -1;
    } else {
      std::unordered_map<long, std::size_t> slave_index;
      for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) slave_index.emplace(scene.slave_ids[i], i);
      for (const io::FrdContact& c : increment.contact) {
        const auto it = slave_index.find(c.node);
        if (it == slave_index.end() || !(c.copen < 0.0)) continue;
        ++row.calculix_contacts;
        const contact::NodeSegmentPair& p = fresh[it->second];
        if (p.status != contact::PairStatus::kFound) continue;
        ++row.calculix_found;
        row.calculix_largest_difference =
            std::max(row.calculix_largest_difference, std::abs(p.label.gap - c.copen));
      }
    }
    previous = fresh;
    rows.push_back(std::move(row));
    if (progress) progress(k + 1, total);
  }
  omp_set_num_threads(saved_threads);
  return rows;
}

namespace {

std::string fmt(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

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

}  // namespace

void write_replay_report(const std::string& directory, const std::string& title, const ReplayOptions& options,
                         const std::vector<IncrementRow>& rows) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path dir(directory);

  // increments.csv: one row per increment, one column group per method.
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
    csv += "\n";
  }
  io::write_text_atomically(dir / "increments.csv", csv);

  // Totals.
  long slaves = 0, found = 0, changed = 0, differences = 0, fresh_lists = 0, tracked = 0, contacts = 0,
       contacts_found = 0;
  double scene_ns = 0.0, fresh_ns = 0.0, tracked_ns = 0.0, calculix_largest = 0.0;
  double fresh_reference_ns = 0.0, tracked_reference_ns = 0.0;
  long reference_faces = 0, reference_differences = 0;
  std::array<long, 3> locations{};
  std::vector<MethodTotal> totals;
  bool calculix = false;
  for (const IncrementRow& r : rows) {
    slaves += r.slaves;
    found += r.found;
    changed += r.faces_changed;
    differences += r.tracking_differences;
    fresh_lists += r.tracking.fresh;
    tracked += r.tracking.tracked;
    scene_ns += r.ns_scene * static_cast<double>(r.slaves);
    fresh_ns += r.ns_fresh * static_cast<double>(r.slaves);
    tracked_ns += r.ns_tracked * static_cast<double>(r.slaves);
    fresh_reference_ns += r.ns_fresh_reference * static_cast<double>(r.slaves);
    tracked_reference_ns += r.ns_tracked_reference * static_cast<double>(r.slaves);
    reference_faces += r.reference_faces;
    reference_differences += r.reference_differences;
    for (int k = 0; k < 3; ++k)
      locations[static_cast<std::size_t>(k)] += r.locations[static_cast<std::size_t>(k)];
    if (r.calculix_contacts >= 0) {
      calculix = true;
      contacts += r.calculix_contacts;
      contacts_found += r.calculix_found;
      calculix_largest = std::max(calculix_largest, r.calculix_largest_difference);
    }
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
  const auto per = [](double total_ns, long count) {
    return count > 0 ? total_ns / static_cast<double>(count) : 0.0;
  };

  std::string md = "# Replay: " + eval::xml_escape(title) + "\n\n";
  md += std::to_string(rows.size()) + " increments, " + std::string(to_string(options.search.surface)) +
        " surface, " + std::to_string(options.threads) + " thread(s); timings are the fastest of " +
        std::to_string(options.repeats) +
        " runs of each call (tracking: each run steps a copy of the tracker).\n\n";
  md += "## Surface search per increment (ns per slave node, over all increments)\n\n";
  md += "| phase | ns per slave node | ratio to fresh |\n|---|---|---|\n";
  md += "| scene (nodes moved, faces, normals) | " + fmt("%.0f", per(scene_ns, slaves)) + " | |\n";
  md += "| fresh surface search | " + fmt("%.0f", per(fresh_ns, slaves)) + " | 1 |\n";
  md += "| tracked surface search | " + fmt("%.0f", per(tracked_ns, slaves)) + " | " +
        fmt("%.3f", fresh_ns > 0 ? tracked_ns / fresh_ns : 0.0) + " |\n";
  if (fresh_reference_ns > 0.0 && fresh_ns > 0.0) {
    md += "| fresh, reference narrow phase (the search before the certificate) | " +
          fmt("%.0f", per(fresh_reference_ns, slaves)) + " | " + fmt("%.3f", fresh_reference_ns / fresh_ns) +
          " |\n";
    md += "| tracked, reference narrow phase | " + fmt("%.0f", per(tracked_reference_ns, slaves)) + " | " +
          fmt("%.3f", tracked_reference_ns / fresh_ns) + " |\n";
  }
  md += "\n";
  md += "Narrow phase: " + std::to_string(reference_faces) +
        " faces needed the reference (no certificate) over all slave node states";
  if (fresh_reference_ns > 0.0) {
    md += "; " + std::to_string(reference_differences) +
          " fresh answers differ from the reference search's (status, face, location; point or gap by more "
          "than "
          "1e-10 of the face size)";
  }
  md += ".\n\n";
  md += "Tracking: " + std::to_string(differences) + " answers of " + std::to_string(slaves) +
        " differ from the fresh search's (face, point to 1e-12, gap); " + std::to_string(fresh_lists) +
        " fresh lists, " + std::to_string(tracked) + " nodes answered from their lists (margin " +
        fmt("%g", options.tracking.margin_relative) +
        " x the capture distance). Points found: " + std::to_string(found) + " (face " +
        std::to_string(locations[0]) + ", edge " + std::to_string(locations[1]) + ", vertex " +
        std::to_string(locations[2]) + "); " + std::to_string(changed) +
        " times a node moved to another face.\n\n";
  if (differences > 0) {
    md +=
        "The first tracked answers that differ (at most 5 per increment):\n\n| increment | slave node | "
        "fresh | tracked "
        "|\n|---|---|---|---|\n";
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
        "tracked / "
        "fresh is " +
        fmt("%.3f", fresh_later > 0 ? tracked_later / fresh_later : 0.0) + ".\n\n";
  }
  if (calculix) {
    md += "CalculiX: " + std::to_string(contacts) + " contacts (COPEN < 0) of this pair's slave nodes, " +
          std::to_string(contacts_found) + " with a point; largest |gap - COPEN| " +
          fmt("%.3g", calculix_largest) + " (scripts/calculix-compare states the .frd's precision).\n\n";
  }
  md += "## Local search on the pairs inside faces (all increments)\n\n";
  md +=
      "Cold methods on every point inside a segment face; start+newton:K from the previous increment's point "
      "on the "
      "nodes that keep their face. Error: max(|d xi|, |d eta|) against the surface search's point, local "
      "units.\n\n";
  md +=
      "| method | queries | ns per query | mean \\|error\\| | max \\|error\\| | failures "
      "|\n|---|---|---|---|---|---|\n";
  int smallest_warm = -1;
  for (const MethodTotal& t : totals) {
    const double mean = t.judged > 0 ? t.error_sum / static_cast<double>(t.judged) : 0.0;
    md += "| " + t.method + " | " + std::to_string(t.queries) + " | " +
          fmt("%.1f", per(t.ns_sum, t.queries)) + " | " + fmt("%.3g", mean) + " | " +
          fmt("%.3g", t.max_error) + " | " + std::to_string(t.failures) + " |\n";
    if (smallest_warm < 0 && t.method.rfind("start+newton:", 0) == 0 && t.queries > 0 && mean <= 1e-10 &&
        t.failures == 0) {
      smallest_warm = std::stoi(t.method.substr(13));
    }
  }
  md += "\nSmallest K for which start+newton:K reaches the surface search's points to 1e-10 (mean): " +
        (smallest_warm >= 0 ? std::to_string(smallest_warm) : std::string("none of those run")) + ".\n\n";
  md +=
      "## Per increment\n\n| increment | time | found | face / edge / vertex | faces changed | tracking "
      "differences | "
      "fresh lists | ns fresh | ns tracked |" +
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
      "location](locations.svg); "
      "the numbers: increments.csv.\n";
  io::write_text_atomically(dir / "report.md", md);

  // Plots over the increments.
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
  for (std::size_t j = 0; j < totals.size(); ++j) {
    errors.push_back({totals[j].method, series([&](const IncrementRow& r) {
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

}  // namespace contactnn::history
