#include "study/scene_report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "eval/report.hpp"
#include "io/json_text.hpp"
#include "study/study_detail.hpp"

namespace contactnn::study {

using detail::network_name;
using io::detail::json_number;
using io::detail::json_string;

void judge_on_pairs(const ScenePairs& pairs, SurfaceKind surface,
                    const std::vector<const SceneNetwork*>& networks, SceneStudyResult& result) {
  result.face_errors.clear();
  result.quad4_errors.clear();
  for (const MethodMeasurement& m : result.measured) {
    const search::LocalSearch search = method_search(surface, m, networks);
    for (const auto& [set, errors] :
         {std::pair{&pairs.face, &result.face_errors}, std::pair{&pairs.quad4_pairs, &result.quad4_errors}}) {
      eval::MethodErrors me =
          eval::compare_with_labels(m.name, eval::run_on_set(search, *set, result.options.threads), *set,
                                    result.options.failure_box_margin, false);
      std::vector<std::int32_t>().swap(me.converged_iterations);
      errors->push_back(std::move(me));
    }
  }
}

bool SceneStudyResult::plan_meets_target_on_pairs() const {
  if (face_errors.empty() || face_errors[chosen].rows == 0) return true;
  const eval::MethodErrors& e = face_errors[chosen];
  return e.failures_method == 0 && std::max(e.stats[0].mean_abs, e.stats[1].mean_abs) <= options.target;
}

namespace {

std::string g4(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

double worse_mean(const eval::MethodErrors& e) { return std::max(e.stats[0].mean_abs, e.stats[1].mean_abs); }

/// The report's table of every method measured (held-out, face pairs, quad4 pairs), with its lead-in.
std::string methods_table(const SceneStudyResult& r, bool any_face) {
  const auto names = coordinate_names(r.surface);
  const SceneStudyOptions& o = r.options;
  std::ostringstream md;
  md << "Every method measured: held-out effective mean |error| (the larger coordinate's mean |error|, each "
        "failure "
        "counting as one domain width; "
     << names[0] << " units, domain width " << (r.surface == SurfaceKind::kGregory ? "1" : "2")
     << ") and time per query (batched, 1 thread, this machine) on the scene's domain, where the plan is "
        "chosen; "
        "then the mean |error| on the deck's pairs inside a face, and on every pair on a quadrilateral "
        "(edges and "
        "vertices included). The plan's row is in bold.\n\n";
  md << "| method | held-out effective mean | reaches " << g4(o.margin) << " x " << g4(o.target)
     << " | ns/query batched | face pairs mean abs " << names[0] << " | mean abs " << names[1]
     << " | max abs | failures | quad4 pairs mean abs |\n|---|---:|:---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t i = 0; i < r.measured.size(); ++i) {
    const MethodMeasurement& m = r.measured[i];
    const std::string name = i == r.chosen ? "**" + m.name + "**" : m.name;
    md << "| " << name << " | " << g4(m.effective_mean) << " | " << (m.reaches ? "yes" : "no") << " | "
       << g4(m.batched_ns) << " | ";
    if (any_face) {
      const eval::MethodErrors& e = r.face_errors[i];
      md << g4(e.stats[0].mean_abs) << " | " << g4(e.stats[1].mean_abs) << " | "
         << g4(std::max(e.stats[0].max_abs, e.stats[1].max_abs)) << " | " << e.failures_method << " | ";
    } else {
      md << "- | - | - | - | ";
    }
    md << (r.quad4_errors.empty() || r.quad4_errors[i].rows == 0 ? std::string("-")
                                                                 : g4(worse_mean(r.quad4_errors[i])))
       << " |\n";
  }
  return md.str();
}

}  // namespace

std::string report_markdown(const SceneStudyResult& r) {
  const auto names = coordinate_names(r.surface);
  const SceneStudyOptions& o = r.options;
  const MethodMeasurement& plan = r.plan();
  const bool any_face = !r.face_errors.empty() && r.face_errors.front().rows > 0;
  std::ostringstream md;
  md << "# scene-study: `" << std::filesystem::path(r.deck).filename().string() << "` pair " << r.pair << ", "
     << to_string(r.surface) << "\n\n";
  md << "- command: `" << r.command_line << "`\n";
  md << "- **plan: `" << plan.method << "`";
  if (plan.network >= 0) {
    md << " with the network " << r.training.tried[static_cast<std::size_t>(plan.network)].name
       << "** (`network.h5`)";
  } else {
    md << "** (no network)";
  }
  md << ": " << (plan.reaches ? "the fastest" : "none reached the target; the most accurate") << " of the "
     << r.measured.size() << " methods measured on a held-out sample of the scene's domain ("
     << r.heldout_rows << " configurations), "
     << (plan.reaches ? "among those whose effective mean |error| is at most " + g4(o.margin) +
                            " x the target " + g4(o.target)
                      : std::string("target ") + g4(o.target))
     << ": held-out " << g4(plan.effective_mean) << ", " << g4(plan.batched_ns)
     << " ns/query batched on 1 thread. Written to `plan.toml`.\n";
  md << "- the deck's pairs: " << r.slave_nodes << " slave nodes; the closest point lies inside a face for "
     << r.locations[0] << ", on an edge for " << r.locations[1] << ", at a vertex for " << r.locations[2]
     << "; " << r.no_segment << " without a face (no_segment). " << r.quad4
     << " lie on 4-node quadrilaterals (the "
     << "local search's segments, SPEC 7), " << (any_face ? r.face_errors.front().rows : 0)
     << " of them inside the face. Edge and vertex answers are the surface search's own and need no local "
        "search: "
        "the methods are judged on the pairs inside a 4-node quadrilateral.\n";
  if (any_face) {
    const eval::MethodErrors& e = r.face_errors[r.chosen];
    md << "- on those " << e.rows << " pairs the plan's method errs " << g4(e.stats[0].mean_abs) << " / "
       << g4(e.stats[1].mean_abs) << " (mean |error| " << names[0] << " / " << names[1] << ", "
       << e.failures_method << " failures): target " << g4(o.target) << " "
       << (r.plan_meets_target_on_pairs() ? "met" : "**not met**") << "\n";
  } else {
    md << "- no pair of the deck lies inside a 4-node quadrilateral: the plan rests on the scene's domain "
          "alone\n";
  }
  md << "- the scene's domain: its "
     << "master segments deformed by " << g4(r.domain.deformation)
     << " of the shortest edge, the slave within " << g4(r.domain.capture)
     << " of it along the normal (the deck's own offsets reach " << g4(r.deck_offset)
     << (o.capture_pairs == "surface" ? ", on its surface-search pairs on quadrilaterals"
                                      : ", on its nearest-node pairs")
     << ")";
  md << "; drawn from "
     << (o.domain_states == DomainStates::kHistory
             ? "the whole history: the deck and its " + std::to_string(r.history_increments) +
                   " increments of `" + r.results + "`"
             : std::string("the deck's own state"));
  if (r.surface == SurfaceKind::kGregory)
    md << ", node normals tilted by up to " << g4(r.domain.normal_tilt_tangent);
  md << ", " << g4(r.domain.boundary_fraction) << " of the foot points on the boundary; " << o.count
     << " configurations to train from (seed " << o.seed << "), " << r.heldout_rows << " held out (seed "
     << r.heldout_seed << ")\n";
  if (!r.training.tried.empty()) {
    md << "- scene networks (" << o.input_features << " inputs, online back-propagation, learning rate "
       << g4(o.learning_rate) << "): ";
    for (std::size_t i = 0; i < r.training.tried.size(); ++i) {
      const SceneNetwork& n = r.training.tried[i];
      md << (i ? ", " : "") << n.name << " with " << n.epochs << " epochs (held-out " << g4(n.heldout_error())
         << ", " << g4(n.seconds) << " s)";
    }
    const SceneNetwork& scene = r.training.tried[static_cast<std::size_t>(r.training.scene)];
    md << "; the scene network is **" << scene.name << "**, "
       << (r.training.reached ? "the first within " + g4(o.margin) + " x the target"
                              : "the best (none came within " + g4(o.margin) + " x the target)")
       << "; " << g4(r.training.seconds) << " s of training\n";
  }
  for (const std::string& why : r.not_trained) md << "- " << why << "\n";
  md << "- " << r.node_orders.summary() << "\n";
  md << "- time: to the plan " << g4(r.seconds_to_plan) << " s, whole study " << g4(r.seconds) << " s\n\n";
  md << methods_table(r, any_face);
  if (!r.history_markdown.empty()) md << "\n" << r.history_markdown;
  return md.str();
}

std::string report_json(const SceneStudyResult& r) {
  const SceneStudyOptions& o = r.options;
  const bool any_face = !r.face_errors.empty() && r.face_errors.front().rows > 0;
  const SceneNetwork* scene =
      r.training.scene >= 0 ? &r.training.tried[static_cast<std::size_t>(r.training.scene)] : nullptr;
  const auto find = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < r.measured.size(); ++i) {
      if (r.measured[i].name == name) return static_cast<int>(i);
    }
    return -1;
  };
  const int scene_row = scene != nullptr ? find("network[" + scene->name + "]") : -1;
  const auto pair_means = [&](int i) {
    if (i < 0 || !any_face) return std::string("null");
    const eval::MethodErrors& e = r.face_errors[static_cast<std::size_t>(i)];
    return "[" + json_number(e.stats[0].mean_abs) + ", " + json_number(e.stats[1].mean_abs) + "]";
  };
  std::ostringstream j;
  j << "{\n  \"deck\": " << json_string(r.deck) << ",\n  \"pair\": " << r.pair
    << ",\n  \"surface\": " << json_string(std::string(to_string(r.surface)))
    << ",\n  \"target\": " << json_number(o.target) << ",\n  \"margin\": " << json_number(o.margin)
    << ",\n  \"count\": " << o.count << ",\n  \"seed\": " << o.seed << ",\n  \"epochs\": " << o.epochs
    << ",\n  \"long_epochs\": " << o.long_epochs << ",\n  \"second_layer\": " << o.second_layer
    << ",\n  \"input_features\": " << json_string(o.input_features)
    << ",\n  \"train_networks\": " << json_string(std::string(to_string(o.train_networks)))
    << ",\n  \"domain\": " << json_string(std::string(to_string(o.domain_states)))
    << ",\n  \"capture_pairs\": " << json_string(o.capture_pairs) << ",\n  \"sizes_tried\": [";
  for (std::size_t i = 0; i < r.training.tried.size(); ++i) {
    const SceneNetwork& n = r.training.tried[i];
    j << (i ? ", " : "") << "{\"hidden\": " << n.hidden << ", \"epochs\": " << n.epochs
      << ", \"name\": " << json_string(n.name) << ", \"heldout_mean_abs\": ["
      << json_number(n.heldout_mean_abs[0]) << ", " << json_number(n.heldout_mean_abs[1])
      << "], \"train_seconds\": " << json_number(n.seconds) << "}";
  }
  j << "],\n  \"network\": "
    << (scene ? json_string(network_name(r.surface, scene->hidden, r.options.second_layer)) : "null")
    << ",\n  \"chosen_hidden\": " << (scene ? std::to_string(scene->hidden) : "null")
    << ",\n  \"chosen_epochs\": " << (scene ? std::to_string(scene->epochs) : "null")
    << ",\n  \"network_reached\": " << (r.training.reached ? "true" : "false")
    << ",\n  \"scene_mean_abs\": " << pair_means(scene_row) << ",\n  \"meets_target\": "
    << (scene_row >= 0 && any_face &&
                worse_mean(r.face_errors[static_cast<std::size_t>(scene_row)]) <= o.target
            ? "true"
            : "false")
    << ",\n  \"pairs\": " << (any_face ? r.face_errors.front().rows : 0)
    << ",\n  \"quad4_pairs\": " << r.quad4 << ",\n  \"locations\": {\"face\": " << r.locations[0]
    << ", \"edge\": " << r.locations[1] << ", \"vertex\": " << r.locations[2] << "}"
    << ",\n  \"node_orders\": " << json_string(r.node_orders.summary())
    << ",\n  \"node_orders_passed\": " << (r.node_orders.passed ? "true" : "false")
    << ",\n  \"seconds_to_plan\": " << json_number(r.seconds_to_plan)
    << ",\n  \"seconds\": " << json_number(r.seconds)
    << ",\n  \"plan\": {\"method\": " << json_string(r.plan().method)
    << ", \"name\": " << json_string(r.plan().name)
    << ", \"reaches\": " << (r.plan().reaches ? "true" : "false")
    << ", \"heldout_effective_mean\": " << json_number(r.plan().effective_mean)
    << ", \"batched_ns\": " << json_number(r.plan().batched_ns)
    << ", \"pairs_mean_abs\": " << pair_means(static_cast<int>(r.chosen))
    << ", \"meets_target_on_pairs\": " << (r.plan_meets_target_on_pairs() ? "true" : "false")
    << "},\n  \"methods\": [";
  for (std::size_t i = 0; i < r.measured.size(); ++i) {
    const MethodMeasurement& m = r.measured[i];
    j << (i ? "," : "") << "\n    {\"method\": " << json_string(m.name)
      << ", \"heldout_effective_mean\": " << json_number(m.effective_mean)
      << ", \"batched_ns\": " << json_number(m.batched_ns)
      << ", \"reaches\": " << (m.reaches ? "true" : "false")
      << ", \"mean_abs\": " << pair_means(static_cast<int>(i)) << ", \"quad4_mean_abs\": "
      << (r.quad4_errors.empty() || r.quad4_errors[i].rows == 0
              ? std::string("null")
              : "[" + json_number(r.quad4_errors[i].stats[0].mean_abs) + ", " +
                    json_number(r.quad4_errors[i].stats[1].mean_abs) + "]")
      << "}";
  }
  j << "\n  ]";
  if (!r.history_json.empty()) j << ",\n  \"history\": " << r.history_json;
  j << "\n}\n";
  return j.str();
}

}  // namespace contactnn::study
