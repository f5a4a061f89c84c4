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
#include "history/run_states.hpp"
#include "io/csv.hpp"
#include "search/local_search.hpp"

namespace contactnn::history {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Faces, points (to 1e-12 of their magnitude) and gaps equal: the tracked search answered as the fresh one.
bool same_answer(const contact::Contact& a, const contact::Contact& b) {
  if (a.status != b.status) return false;
  if (a.status != contact::PairStatus::kFound) return true;
  const double tol = 1e-12 * (1.0 + a.point.norm());
  return a.face == b.face && (a.point - b.point).norm() <= tol && std::abs(a.gap - b.gap) <= tol;
}

/// Face f's size: its longest corner distance.
double face_size(const mesh::SurfaceMesh& master, int f) {
  double size = 0.0;
  for (const int i : master.face_corners(f)) {
    for (const int j : master.face_corners(f)) {
      size = std::max(size, (master.positions[static_cast<std::size_t>(i)] -
                             master.positions[static_cast<std::size_t>(j)])
                                .norm());
    }
  }
  return size;
}

/// The same answer as the reference search's to 1e-10 of the face's size: status, face and location, the
/// point and the gap.
bool same_as_reference(const mesh::SurfaceMesh& master, const contact::Contact& a,
                       const contact::Contact& b) {
  if (a.status != b.status) return false;
  if (a.status != contact::PairStatus::kFound) return true;
  if (a.face != b.face || a.location != b.location) return false;
  const double tol = 1e-10 * face_size(master, a.face);
  return (a.point - b.point).norm() <= tol && std::abs(a.gap - b.gap) <= tol;
}

/// One answer as a report cell: status, or face, location, point and gap.
std::string answer_cell(const contact::Contact& p) {
  if (p.status != contact::PairStatus::kFound) return "no_segment";
  static constexpr const char* kWhere[] = {"face", "edge", "vertex"};
  char text[200];
  std::snprintf(text, sizeof text, "face %d (%s), P (%.17g, %.17g, %.17g), gap %.17g", p.face,
                kWhere[static_cast<int>(p.location)], p.point.x(), p.point.y(), p.point.z(), p.gap);
  return text;
}

/// A node whose tracked answer differs from the fresh one, as a Markdown table row.
std::string difference_row(int increment, const contact::Contact& fresh, const contact::Contact& tracked) {
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

Queries face_queries(const contact::Scene& scene, const std::vector<contact::Contact>& pairs,
                     SurfaceKind kind, const std::vector<char>* only) {
  Queries q;
  const bool gregory = kind == SurfaceKind::kGregory;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const contact::Contact& p = pairs[i];
    if (p.status != contact::PairStatus::kFound || p.location != Location::kFace) continue;
    // lib/search's methods are for the segments' quad4 surfaces (a C3D20 face is a quad8 for the search).
    if (static_cast<std::size_t>(p.face) >= scene.master.segments.size()) continue;
    if (scene.master.face_type(p.face) != mesh::FaceType::kQuad4) continue;
    if (only != nullptr && (*only)[i] == 0) continue;
    const auto& quad = scene.master.segments[static_cast<std::size_t>(p.face)];
    for (int n : quad) {
      for (int k = 0; k < 3; ++k) q.raw.push_back(scene.master.positions[static_cast<std::size_t>(n)][k]);
    }
    for (int k = 0; k < 3; ++k) q.raw.push_back(scene.slave_positions[i][k]);
    if (gregory) {
      for (int n : quad) {
        for (int k = 0; k < 3; ++k) q.raw.push_back(scene.master_normals[static_cast<std::size_t>(n)][k]);
      }
    }
    q.reference.push_back(p.param);
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

/// The replay's state from one increment to the next: the trackers and the answer buffers (kept, as an FE
/// code's would be), and the steps of one increment (replay's header comment), each a member.
class Replayer {
 public:
  explicit Replayer(const ReplayOptions& options)
      : options_(options),
        repeats_(std::max(options.repeats, 1)),
        reference_options_(with_narrow(options.search, contact::NarrowPhase::kReference)),
        plan_options_(with_interior(options.search, options.plan)),
        beside_(options.beside_reference && options.search.narrow != contact::NarrowPhase::kReference),
        tracker_(static_cast<std::size_t>(repeats_),
                 contact::SurfaceTracker(options.search, options.tracking)),
        reference_tracker_(static_cast<std::size_t>(repeats_),
                           contact::SurfaceTracker(reference_options_, options.tracking)),
        plan_tracker_(static_cast<std::size_t>(repeats_),
                      contact::SurfaceTracker(plan_options_, options.tracking)) {}

  IncrementRow increment(RunStates& run, std::size_t k) {
    const io::FrdIncrement& increment = run.increment(k);
    IncrementRow row;
    row.increment = increment.number;
    row.step = increment.step;
    row.time = increment.time;
    // 1. The state: the pair's nodes moved, its node normals (the faces and slave nodes are built once).
    const auto start = Clock::now();
    const contact::Scene& scene = run.move_to(k);
    const double scene_seconds = seconds_since(start);
    row.slaves = static_cast<long>(scene.slave_ids.size());
    per_node_ = row.slaves > 0 ? 1e9 / static_cast<double>(row.slaves) : 0.0;
    row.ns_scene = scene_seconds * per_node_;
    search(scene, row);               // 2. the surface search, fresh and tracked, beside the reference's
    plan(scene, row);                 // 2b. the plan's search, judged against the exact one
    methods(scene, row);              // 3. the local-search methods on the pairs inside faces
    calculix(increment, scene, row);  // 4. CalculiX's contact output
    previous_ = fresh_;
    return row;
  }

 private:
  static contact::SearchOptions with_narrow(contact::SearchOptions o, contact::NarrowPhase narrow) {
    o.narrow = narrow;
    return o;
  }
  static contact::SearchOptions with_interior(contact::SearchOptions o, const contact::FaceLocator* plan) {
    o.interior = plan;
    return o;
  }

  /// The fastest of `repeats` fresh searches with `search`, ns per slave node (answers in `out`); the faces'
  /// tables in memory kept from the last search (as an FE code's handle with tracking off keeps it).
  double time_fresh(const contact::Scene& scene, const contact::SearchOptions& search,
                    std::vector<contact::Contact>& out) {
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < repeats_; ++r) {
      const auto start = Clock::now();
      contact::surface_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions,
                              search, out, &fresh_storage_);
      best = std::min(best, seconds_since(start));
    }
    return best * per_node_;
  }

  /// The same for a tracked step: tracking keeps state, so each of `repeats` trackers steps through every
  /// state (each its own history, as an FE code's: its grid, lists and kept faces; a copy of one would start
  /// without the faces' tables, SearchStorage), and the fastest step counts. They answer alike (the answers
  /// never depend on what a tracker keeps); the first one's are in `out`.
  double time_tracked(const contact::Scene& scene, std::vector<contact::SurfaceTracker>& trackers,
                      std::vector<contact::Contact>& out, contact::TrackingCounts* counts) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t r = 0; r < trackers.size(); ++r) {
      std::vector<contact::Contact>& answers = r == 0 ? out : spare_;
      const auto start = Clock::now();
      trackers[r].step(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, answers,
                       r == 0 ? counts : nullptr);
      best = std::min(best, seconds_since(start));
    }
    return best * per_node_;
  }

  void search(const contact::Scene& scene, IncrementRow& row) {
    row.ns_fresh = time_fresh(scene, options_.search, fresh_);
    row.ns_tracked = time_tracked(scene, tracker_, tracked_, &row.tracking);
    for (const contact::Contact& p : fresh_) row.reference_faces += p.reference_faces;
    if (beside_) {
      // The search as it was, timed the same way beside this one; the fresh answers compared.
      row.ns_fresh_reference = time_fresh(scene, reference_options_, reference_);
      row.ns_tracked_reference = time_tracked(scene, reference_tracker_, reference_tracked_, nullptr);
      for (std::size_t i = 0; i < fresh_.size(); ++i) {
        if (!same_as_reference(scene.master, fresh_[i], reference_[i])) ++row.reference_differences;
      }
    }
    kept_.assign(fresh_.size(), 0);
    for (std::size_t i = 0; i < fresh_.size(); ++i) {
      if (!same_answer(fresh_[i], tracked_[i])) {
        ++row.tracking_differences;
        if (row.differences.size() < 5)
          row.differences.push_back(difference_row(row.increment, fresh_[i], tracked_[i]));
      }
      if (fresh_[i].status != contact::PairStatus::kFound) continue;
      ++row.found;
      ++row.locations[static_cast<std::size_t>(fresh_[i].location)];
      if (previous_.size() == fresh_.size() && previous_[i].status == contact::PairStatus::kFound) {
        if (previous_[i].face == fresh_[i].face) {
          kept_[i] = 1;
        } else {
          ++row.faces_changed;
        }
      }
    }
  }

  void plan(const contact::Scene& scene, IncrementRow& row) {
    if (options_.plan == nullptr) return;
    const double ns_fresh = time_fresh(scene, plan_options_, plan_fresh_);
    const double ns_tracked = time_tracked(scene, plan_tracker_, plan_tracked_, nullptr);
    row.plan = judge_plan(scene.master, options_.search.surface, fresh_, plan_fresh_);
    row.plan.ns_fresh = ns_fresh;
    row.plan.ns_tracked = ns_tracked;
  }

  void methods(const contact::Scene& scene, IncrementRow& row) const {
    const SurfaceKind surface = options_.search.surface;
    const Queries all = face_queries(scene, fresh_, surface, nullptr);
    for (const std::string& m : options_.methods)
      row.methods.push_back(run_method(m, surface, all, options_, nullptr));
    // Warm starts on the nodes that keep their face.
    const Queries warm = face_queries(scene, fresh_, surface, &kept_);
    std::vector<double> starts;
    for (std::size_t j = 0; j < warm.node.size(); ++j) {
      starts.push_back(previous_[warm.node[j]].param[0]);
      starts.push_back(previous_[warm.node[j]].param[1]);
    }
    for (int steps : options_.warm_steps) {
      row.methods.push_back(
          run_method("start+newton:" + std::to_string(steps), surface, warm, options_, &starts));
    }
  }

  /// Every slave node of this pair CalculiX reports in contact (COPEN < 0), against the fresh answer.
  void calculix(const io::FrdIncrement& increment, const contact::Scene& scene, IncrementRow& row) const {
    if (increment.contact.empty()) {
      row.calculix_contacts = -1;
      return;
    }
    std::unordered_map<long, std::size_t> slave_index;
    for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) slave_index.emplace(scene.slave_ids[i], i);
    for (const io::FrdContact& c : increment.contact) {
      const auto it = slave_index.find(c.node);
      if (it == slave_index.end() || !(c.copen < 0.0)) continue;
      ++row.calculix_contacts;
      const contact::Contact& p = fresh_[it->second];
      if (p.status != contact::PairStatus::kFound) continue;
      ++row.calculix_found;
      row.calculix_largest_difference = std::max(row.calculix_largest_difference, std::abs(p.gap - c.copen));
    }
  }

  const ReplayOptions& options_;
  int repeats_;
  contact::SearchOptions reference_options_, plan_options_;
  bool beside_;
  double per_node_ = 0.0;
  std::vector<contact::SurfaceTracker> tracker_, reference_tracker_, plan_tracker_;  ///< time_tracked's
  contact::SearchStorage fresh_storage_;                                             ///< time_fresh's
  std::vector<contact::Contact> previous_, fresh_, tracked_, reference_, reference_tracked_;
  std::vector<contact::Contact> spare_;  ///< the answers of the trackers after the first
  std::vector<contact::Contact> plan_fresh_, plan_tracked_;
  std::vector<char> kept_;  ///< nodes whose fresh face is the previous increment's
};

/// Checks the methods of `options` before any work: InvalidArgument for a network method without a network
/// or a warm method among the cold ones.
void check_methods(const ReplayOptions& options) {
  for (const std::string& m : options.methods) {
    const search::Method method = search::Method::parse(m);
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_network() || options.network != nullptr,
                         "method '" << m << "' needs a network (--weights)");
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_start(),
                         "method '" << m << "': warm starts are --warm_steps");
  }
}

/// One domain width of a face's local coordinates (PlanRow::mean_error's count for a point on another face).
double domain_width(const mesh::SurfaceMesh& master, SurfaceKind surface, int f) {
  const mesh::FaceType type = master.face_type(f);
  if (type == mesh::FaceType::kQuad8) return 2.0;
  if (type != mesh::FaceType::kQuad4) return 1.0;
  const bool segment = static_cast<std::size_t>(f) < master.segments.size();
  return segment && surface == SurfaceKind::kGregory ? 1.0 : 2.0;
}

}  // namespace

PlanRow judge_plan(const mesh::SurfaceMesh& master, SurfaceKind surface,
                   const std::vector<contact::Contact>& exact, const std::vector<contact::Contact>& plan) {
  CONTACTNN_REQUIRE(exact.size() == plan.size(), exact.size() << " exact answers for " << plan.size());
  PlanRow row;
  double error_sum = 0.0, distance_sum = 0.0;
  long both = 0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const contact::Contact& e = exact[i];
    const contact::Contact& p = plan[i];
    const bool found = p.status == contact::PairStatus::kFound;
    if (found && p.by_method) ++row.by_method;
    if (e.status != contact::PairStatus::kFound) continue;
    if (!found) {
      ++row.refused;
      continue;
    }
    if (!p.by_method && e.location == Location::kFace) ++row.fallbacks;
    if (p.face != e.face) ++row.other_face;
    const double distance = (p.point - e.point).norm() / face_size(master, e.face);
    distance_sum += distance;
    row.max_distance = std::max(row.max_distance, distance);
    ++both;
    if (!p.by_method) continue;
    const double error = p.face != e.face
                             ? domain_width(master, surface, e.face)
                             : std::max(std::abs(p.param[0] - e.param[0]), std::abs(p.param[1] - e.param[1]));
    error_sum += error;
    row.max_error = std::max(row.max_error, error);
  }
  row.mean_error = row.by_method > 0 ? error_sum / static_cast<double>(row.by_method) : 0.0;
  row.mean_distance = both > 0 ? distance_sum / static_cast<double>(both) : 0.0;
  return row;
}

std::vector<IncrementRow> replay(mesh::ContactModel model, const io::FrdResults& results,
                                 const ReplayOptions& options,
                                 const std::function<void(int, int)>& progress) {
  check_methods(options);
  RunStates run(std::move(model), options.pair, &results);
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(std::max(options.threads, 1));
  Replayer replayer(options);
  std::vector<IncrementRow> rows;
  const int total = static_cast<int>(run.count());
  for (int k = 0; k < total; ++k) {
    rows.push_back(replayer.increment(run, static_cast<std::size_t>(k)));
    if (progress) progress(k + 1, total);
  }
  omp_set_num_threads(saved_threads);
  return rows;
}

}  // namespace contactnn::history
