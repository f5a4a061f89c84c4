#include "study/scene_history.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "contact/narrow_phase.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "history/run_states.hpp"
#include "io/csv.hpp"
#include "io/json_text.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"

namespace contactnn::study {

using io::detail::json_number;
using io::detail::json_string;

namespace {

std::string g4(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

std::string percent(double fraction) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f%%", 100.0 * fraction);
  return b;
}

const search::NetworkModel* model_of(const std::vector<const SceneNetwork*>& networks, int index) {
  return index >= 0 ? networks.at(static_cast<std::size_t>(index))->model.get() : nullptr;
}

/// The plan's surface search over every increment.
struct SearchTotals {
  long by_method = 0, fallbacks = 0, refused = 0;
};

SearchTotals search_totals(const HistoryJudgement& j) {
  SearchTotals t;
  for (const history::PlanRow& p : j.plan_search) {
    t.by_method += p.by_method;
    t.fallbacks += p.fallbacks;
    t.refused += p.refused;
  }
  return t;
}

/// The plan's method as the surface search's face locator (null without a plan's method among `methods`).
std::unique_ptr<contact::FaceLocator> plan_locator(const std::vector<HistoryMethod>& methods,
                                                   const std::vector<const SceneNetwork*>& networks) {
  for (const HistoryMethod& m : methods) {
    if (m.plan) return std::make_unique<contact::FaceLocator>(m.method, model_of(networks, m.network));
  }
  return nullptr;
}

/// The surface search with the plan's method on face interiors (as replay --plan runs it) at one state,
/// judged against the exact search's answers `exact` (history::judge_plan).
history::PlanRow plan_search(const contact::Scene& scene, SurfaceKind surface,
                             const contact::FaceLocator& locator,
                             const std::vector<contact::NodeSegmentPair>& exact) {
  contact::SearchOptions options = pairs_search_options(surface);
  options.interior = &locator;
  std::vector<contact::Contact> plan, exact_contacts(exact.size());
  contact::surface_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, options,
                          plan);
  std::transform(exact.begin(), exact.end(), exact_contacts.begin(), contact::contact_of);
  return history::judge_plan(scene.master, surface, exact_contacts, plan);
}

}  // namespace

std::vector<HistoryState> history_states(mesh::ContactModel model, const io::FrdResults& results, int pair,
                                         const StudyLog& log) {
  history::RunStates run(std::move(model), pair, &results);
  std::vector<HistoryState> states;
  states.reserve(results.increments.size());
  for (std::size_t i = 0; i < results.increments.size(); ++i) {
    HistoryState s;
    s.increment = results.increments[i].number;
    s.step = results.increments[i].step;
    s.time = results.increments[i].time;
    s.scene = run.move_to(i);
    states.push_back(std::move(s));
    if (log && ((i + 1) % 10 == 0 || i + 1 == results.increments.size())) {
      log("history: " + std::to_string(i + 1) + " of " + std::to_string(results.increments.size()) +
          " increments of " + results.file + " read");
    }
  }
  return states;
}

bool HistoryJudgement::meets(std::size_t m, std::size_t increment) const {
  const HistoryCell& c = cells.at(m).at(increment);
  if (methods.at(m).plan && !plan_search.empty() && plan_search.at(increment).refused > 0) return false;
  if (c.errors.rows == 0) return true;
  return c.errors.failures_method == 0 && c.worse_mean() <= target &&
         c.out_of_domain_fraction() <= kMaxOutOfDomain;
}

std::size_t HistoryJudgement::worst(std::size_t m) const {
  std::size_t worst = 0;
  const auto key = [&](std::size_t i) {
    const HistoryCell& c = cells[m][i];
    return std::pair<double, double>{static_cast<double>(c.errors.failures_method), c.worse_mean()};
  };
  for (std::size_t i = 1; i < cells.at(m).size(); ++i) {
    if (key(i) > key(worst)) worst = i;
  }
  return worst;
}

std::string HistoryMethod::role() const {
  if (scene && plan) return " (the scene network, the plan's method)";
  if (scene) return " (the scene network)";
  if (plan) return " (the plan's method)";
  return "";
}

std::vector<HistoryMethod> history_methods(const std::vector<const SceneNetwork*>& networks, int scene,
                                           const std::vector<MethodMeasurement>& measured,
                                           std::size_t chosen) {
  std::vector<HistoryMethod> out;
  for (std::size_t k = 0; k < networks.size(); ++k) {
    out.push_back({"network[" + networks[k]->name + "]", "network", static_cast<int>(k), false,
                   static_cast<int>(k) == scene});
  }
  if (chosen < measured.size()) {
    const MethodMeasurement& p = measured[chosen];
    const auto same =
        std::find_if(out.begin(), out.end(), [&](const HistoryMethod& h) { return h.name == p.name; });
    if (same != out.end()) {
      same->plan = true;
    } else {
      out.push_back({p.name, p.method, p.network, true, false});
    }
  }
  return out;
}

HistoryJudgement judge_history(const std::vector<HistoryState>& states, SurfaceKind surface,
                               const std::vector<const SceneNetwork*>& networks,
                               const std::vector<HistoryMethod>& methods, const SceneStudyOptions& options,
                               const StudyLog& log) {
  HistoryJudgement j;
  j.surface = surface;
  j.target = options.target;
  j.methods = methods;
  j.cells.assign(methods.size(), {});
  std::vector<search::LocalSearch> searches;
  for (const HistoryMethod& m : methods) {
    searches.emplace_back(surface, search::Method::parse(m.method), search::SearchOptions{},
                          model_of(networks, m.network));
  }
  // The networks alone: which pairs lie outside their training domains.
  std::vector<search::LocalSearch> alone;
  for (std::size_t k = 0; k < networks.size(); ++k) {
    alone.emplace_back(surface, search::Method::parse("network"), search::SearchOptions{},
                       model_of(networks, static_cast<int>(k)));
  }
  const std::unique_ptr<contact::FaceLocator> locator = plan_locator(methods, networks);
  for (const HistoryState& state : states) {
    const ScenePairs pairs = search_pairs(state.scene, surface);
    if (locator) j.plan_search.push_back(plan_search(state.scene, surface, *locator, pairs.result.pairs));
    j.increments.push_back(state.increment);
    j.steps.push_back(state.step);
    j.times.push_back(state.time);
    j.slave_nodes.push_back(static_cast<long>(state.scene.slave_ids.size()));
    j.no_segment.push_back(pairs.result.no_segment);
    j.locations.push_back(pairs.locations);
    j.quad4.push_back(pairs.quad4);
    const eval::EvaluationSet& set = pairs.face;
    std::vector<long> out_of_domain(networks.size(), 0);
    if (set.rows() > 0) {
      for (std::size_t k = 0; k < networks.size(); ++k) {
        const eval::Estimates e = eval::run_on_set(alone[k], set, options.threads);
        out_of_domain[k] =
            static_cast<long>(std::count(e.status.begin(), e.status.end(), Status::kOutOfDomain));
      }
    }
    for (std::size_t m = 0; m < methods.size(); ++m) {
      HistoryCell cell;
      cell.errors.method = methods[m].name;
      if (set.rows() > 0) {
        cell.errors =
            eval::compare_with_labels(methods[m].name, eval::run_on_set(searches[m], set, options.threads),
                                      set, options.failure_box_margin, false);
        std::vector<std::int32_t>().swap(cell.errors.converged_iterations);
        if (methods[m].network >= 0)
          cell.out_of_domain = out_of_domain[static_cast<std::size_t>(methods[m].network)];
      }
      j.cells[m].push_back(std::move(cell));
    }
    if (log) {
      std::string line = "history: increment " + std::to_string(state.increment) + " (step " +
                         std::to_string(state.step) + ", time " + g4(state.time) +
                         "): " + std::to_string(set.rows()) + " pairs inside a face";
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const HistoryCell& c = j.cells[m].back();
        line += "; " + methods[m].name + " " + g4(c.worse_mean());
        if (methods[m].network >= 0) line += " (" + percent(c.out_of_domain_fraction()) + " out of domain)";
      }
      if (locator) {
        const history::PlanRow& p = j.plan_search.back();
        line += "; the plan's surface search: " + std::to_string(p.by_method) + " by the method, " +
                std::to_string(p.fallbacks) + " fallbacks, " + std::to_string(p.refused) + " refused";
      }
      log(line);
    }
  }
  return j;
}

std::string history_csv(const HistoryJudgement& j) {
  const auto names = coordinate_names(j.surface);
  std::string text;
  io::append_csv_row(text, {"increment",
                            "step",
                            "time",
                            "method",
                            "plan",
                            "scene_network",
                            "domain",
                            "slave_nodes",
                            "face",
                            "edge",
                            "vertex",
                            "no_segment",
                            "pairs",
                            std::string("mean_abs_") + names[0].data(),
                            std::string("mean_abs_") + names[1].data(),
                            "max_abs",
                            "failures",
                            "out_of_domain",
                            "out_of_domain_fraction",
                            "meets_target",
                            "search_by_method",
                            "search_fallbacks",
                            "search_refused"});
  for (std::size_t m = 0; m < j.methods.size(); ++m) {
    for (std::size_t i = 0; i < j.increments.size(); ++i) {
      const HistoryCell& c = j.cells[m][i];
      const bool network = j.methods[m].network >= 0;
      const history::PlanRow* p = j.methods[m].plan && !j.plan_search.empty() ? &j.plan_search[i] : nullptr;
      io::append_csv_row(text, {std::to_string(j.increments[i]),
                                std::to_string(j.steps[i]),
                                io::format_double(j.times[i]),
                                j.methods[m].name,
                                j.methods[m].plan ? "true" : "false",
                                j.methods[m].scene ? "true" : "false",
                                j.domain,
                                std::to_string(j.slave_nodes[i]),
                                std::to_string(j.locations[i][0]),
                                std::to_string(j.locations[i][1]),
                                std::to_string(j.locations[i][2]),
                                std::to_string(j.no_segment[i]),
                                std::to_string(c.errors.rows),
                                c.errors.rows > 0 ? io::format_double(c.errors.stats[0].mean_abs) : "",
                                c.errors.rows > 0 ? io::format_double(c.errors.stats[1].mean_abs) : "",
                                c.errors.rows > 0 ? io::format_double(std::max(c.errors.stats[0].max_abs,
                                                                               c.errors.stats[1].max_abs))
                                                  : "",
                                std::to_string(c.errors.failures_method),
                                network ? std::to_string(c.out_of_domain) : "",
                                network ? io::format_double(c.out_of_domain_fraction()) : "",
                                j.meets(m, i) ? "true" : "false",
                                p != nullptr ? std::to_string(p->by_method) : "",
                                p != nullptr ? std::to_string(p->fallbacks) : "",
                                p != nullptr ? std::to_string(p->refused) : ""});
    }
  }
  return text;
}

std::string history_markdown(const HistoryJudgement& j) {
  const auto names = coordinate_names(j.surface);
  std::ostringstream md;
  if (j.increments.empty()) return "## The history: no increment\n";
  md << "## The history: " << j.increments.size() << " increments of `" << j.results << "`\n\n";
  md << "The deck moved to each increment (SPEC 10: the .frd's node coordinates plus its DISP), the surface "
        "search run, and every scene network alone and the plan's method judged on the increment's pairs "
        "inside "
        "a 4-node quadrilateral face, against the reference: mean |error| in "
     << names[0]
     << " units and the fraction of those pairs outside the network's training domain. The "
        "networks were trained on the domain of "
     << (j.domain == "history" ? "the whole history (the segments of the rest state and of every increment)"
                               : "the rest state (the deck as read)")
     << ". An increment meets the target when the worse coordinate's mean |error| is at most " << g4(j.target)
     << ", no estimate fails, and at most " << percent(kMaxOutOfDomain)
     << " of the pairs are out of the domain. Every row is in `history.csv`.\n\n";
  for (std::size_t m = 0; m < j.methods.size(); ++m) {
    const HistoryMethod& method = j.methods[m];
    long missed = 0;
    double worst_ood = 0.0;
    for (std::size_t i = 0; i < j.increments.size(); ++i) {
      missed += j.meets(m, i) ? 0 : 1;
      worst_ood = std::max(worst_ood, j.cells[m][i].out_of_domain_fraction());
    }
    const std::size_t w = j.worst(m);
    const HistoryCell& c = j.cells[m][w];
    md << "- `" << method.name << "`" << method.role() << ": worst increment " << j.increments[w]
       << " with mean |error| " << g4(c.errors.stats[0].mean_abs) << " / " << g4(c.errors.stats[1].mean_abs)
       << " on " << c.errors.rows << " pairs";
    if (method.network >= 0) md << "; at most " << percent(worst_ood) << " out of domain";
    if (method.plan && !j.plan_search.empty()) {
      const SearchTotals t = search_totals(j);
      md << "; in the surface search " << t.by_method << " points by the method, " << t.fallbacks
         << " fallbacks to the exact point, " << t.refused << " refused (all increments)";
    }
    md << "; "
       << (missed == 0 ? std::string("target met on every increment")
                       : "**target missed on " + std::to_string(missed) + " of " +
                             std::to_string(j.increments.size()) + " increments**")
       << "\n";
  }
  for (std::size_t m = 0; m < j.methods.size(); ++m) {
    const HistoryMethod& method = j.methods[m];
    const bool search = method.plan && !j.plan_search.empty();
    md << "\n### `" << method.name << "`" << method.role() << "\n\n";
    if (search) {
      md << "Search: the surface search with this method on face interiors (as `replay --plan`): the slave "
            "points whose point it gave, the fallbacks (an exact answer inside a face whose point it did not "
            "give) and the refused (a slave point the exact search answers and it does not).\n\n";
    }
    md << "| increment | step | time | slave nodes | face / edge / vertex | pairs inside a face | mean abs "
       << names[0] << " | mean abs " << names[1] << " | max abs | failures | out of domain |"
       << (search ? " search: by the method / fallbacks / refused |" : "") << " target |\n"
       << "|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|" << (search ? "---|" : "") << ":---:|\n";
    for (std::size_t i = 0; i < j.increments.size(); ++i) {
      const HistoryCell& c = j.cells[m][i];
      const bool any = c.errors.rows > 0;
      const std::string searched = search ? " " + std::to_string(j.plan_search[i].by_method) + " / " +
                                                std::to_string(j.plan_search[i].fallbacks) + " / " +
                                                std::to_string(j.plan_search[i].refused) + " |"
                                          : std::string();
      md << "| " << j.increments[i] << " | " << j.steps[i] << " | " << g4(j.times[i]) << " | "
         << j.slave_nodes[i] << " | " << j.locations[i][0] << " / " << j.locations[i][1] << " / "
         << j.locations[i][2] << " | " << c.errors.rows << " | "
         << (any ? g4(c.errors.stats[0].mean_abs) : "-") << " | "
         << (any ? g4(c.errors.stats[1].mean_abs) : "-") << " | "
         << (any ? g4(std::max(c.errors.stats[0].max_abs, c.errors.stats[1].max_abs)) : "-") << " | "
         << c.errors.failures_method << " | "
         << (method.network >= 0 && any
                 ? std::to_string(c.out_of_domain) + " (" + percent(c.out_of_domain_fraction()) + ")"
                 : std::string("-"))
         << " |" << searched << " " << (j.meets(m, i) ? "met" : "**missed**") << " |\n";
    }
  }
  return md.str();
}

std::string history_json(const HistoryJudgement& j) {
  std::ostringstream out;
  out << "{\"results\": " << json_string(j.results) << ", \"increments\": " << j.increments.size()
      << ", \"domain\": " << json_string(j.domain)
      << ", \"max_out_of_domain\": " << json_number(kMaxOutOfDomain) << ", \"methods\": [";
  for (std::size_t m = 0; m < j.methods.size() && !j.increments.empty(); ++m) {
    const std::size_t w = j.worst(m);
    long missed = 0;
    double worst_ood = 0.0;
    for (std::size_t i = 0; i < j.increments.size(); ++i) {
      missed += j.meets(m, i) ? 0 : 1;
      worst_ood = std::max(worst_ood, j.cells[m][i].out_of_domain_fraction());
    }
    const HistoryCell& c = j.cells[m][w];
    out << (m ? ", " : "") << "{\"method\": " << json_string(j.methods[m].name)
        << ", \"plan\": " << (j.methods[m].plan ? "true" : "false")
        << ", \"scene_network\": " << (j.methods[m].scene ? "true" : "false")
        << ", \"worst_increment\": " << j.increments[w] << ", \"worst_mean_abs\": ["
        << json_number(c.errors.stats[0].mean_abs) << ", " << json_number(c.errors.stats[1].mean_abs)
        << "], \"worst_out_of_domain_fraction\": "
        << (j.methods[m].network >= 0 ? json_number(worst_ood) : "null")
        << ", \"increments_missed\": " << missed;
    if (j.methods[m].plan && !j.plan_search.empty()) {
      const SearchTotals t = search_totals(j);
      out << ", \"search\": {\"by_method\": " << t.by_method << ", \"fallbacks\": " << t.fallbacks
          << ", \"refused\": " << t.refused << "}";
    }
    out << "}";
  }
  out << "]}";
  return out.str();
}

}  // namespace contactnn::study
