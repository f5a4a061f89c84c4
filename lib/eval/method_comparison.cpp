#include "eval/method_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "eval/ranking.hpp"
#include "mlp/random.hpp"

namespace contactnn::eval {

namespace {

/// A timed pass is at least this many queries, so that one pass is long enough for the clock and a
/// preemption does not dominate it: small sets (a scene's pairs) are cycled up to it.
constexpr std::int64_t kMinTimingQueries = 4096;

// Classes of configuration by the steps "newton" needs: upper bounds, the last class taking the rest.
constexpr std::array<int, 3> kClassUpper = {5, 7, 10};
constexpr std::array<const char*, 4> kClassLabels = {"1-5 iterations", "6-7 iterations", "8-10 iterations",
                                                     "more than 10 or not converged"};

/// A method of the comparison: its search and which network (index, -1: none) it uses.
struct ComparedMethod {
  std::string name;
  search::Method method;
  int network = -1;
};

std::string trim(std::string s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

std::vector<ComparedMethod> expand_methods(const std::string& list,
                                           const std::vector<EvaluatedNetwork>& networks,
                                           double start_offset) {
  std::vector<ComparedMethod> methods;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    const search::Method m = search::Method::parse(item);
    if (m.needs_start()) {
      CONTACTNN_REQUIRE(start_offset >= 0.0,
                        "method '" << item
                                   << "' refines the caller's own starts (an FE code's "
                                      "previous time step); an evaluation set has none to give it: "
                                      "give --start_offset D to start from each reference point "
                                      "moved D");
      std::ostringstream name;
      name << m.name() << "[" << start_offset << " off]";
      methods.push_back({name.str(), m, -1});
      continue;
    }
    if (!m.needs_network()) {
      methods.push_back({m.name(), m, -1});
      continue;
    }
    CONTACTNN_REQUIRE(!networks.empty(), "method '" << item << "' needs a network: give --weights");
    for (std::size_t k = 0; k < networks.size(); ++k) {
      methods.push_back({m.name() + "[" + networks[k].name + "]", m, static_cast<int>(k)});
    }
  }
  CONTACTNN_REQUIRE(!methods.empty(), "no method to evaluate in '" << list << "'");
  for (std::size_t i = 0; i < methods.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      CONTACTNN_REQUIRE(methods[i].name != methods[j].name,
                        "method '" << methods[i].name << "' is listed twice");
    }
  }
  return methods;
}

/// `list` with each item "default" replaced by `defaults` (all of it when `list` is empty).
std::string with_defaults(const std::string& list, const std::string& defaults) {
  if (list.empty()) return defaults;
  std::string out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    item = trim(item);
    out += (out.empty() ? "" : ",") + (item == "default" ? defaults : item);
  }
  return out;
}

/// `count` queries for timing: distinct usable rows (the label has a point) in random order (seeded, so that
/// no method profits from the set's order), cycled when the set has fewer.
std::vector<std::size_t> timing_rows(const EvaluationSet& set, std::int64_t count, std::uint64_t seed) {
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < set.label_status.size(); ++r) {
    if (set.label_status[r] == Status::kOk || set.label_status[r] == Status::kOutside) rows.push_back(r);
  }
  CONTACTNN_REQUIRE_AS(FormatError, !rows.empty(),
                       "'" << set.source << "' has no row with a reference point to time on");
  mlp::Rng rng(mlp::Rng::derive_seed(seed, 0x7173ULL));
  const std::size_t take = std::min<std::size_t>(rows.size(), static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < take; ++i) {
    const std::size_t j = i + static_cast<std::size_t>(rng.below(rows.size() - i));
    std::swap(rows[i], rows[j]);
  }
  rows.resize(take);
  const auto target = static_cast<std::size_t>(std::max(count, kMinTimingQueries));
  for (std::size_t i = 0; rows.size() < target && i < take * target; ++i) rows.push_back(rows[i % take]);
  return rows;
}

/// Buffers of one timed method: the search and where its results go (allocated once, reused by every pass).
/// start+newton:K overwrites its starts: each pass copies them in first (`start`, 2 doubles a query, timed).
struct Runner {
  search::LocalSearch search;
  const std::vector<double>* raw;
  std::vector<double> param;
  std::vector<Status> status;
  std::size_t n, columns;
  std::vector<double> start;

  Runner(search::LocalSearch s, const std::vector<double>& queries, std::size_t count, std::size_t cols,
         std::vector<double> starts = {})
      : search(std::move(s)),
        raw(&queries),
        param(2 * count),
        status(count),
        n(count),
        columns(cols),
        start(std::move(starts)) {}

  double checksum() const {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += param[2 * i] + 0.5 * param[2 * i + 1];
    return sum;
  }
  /// Every query in one call (lib/search's blocks), on `threads` threads.
  double batched(int threads) {
    if (!start.empty()) std::copy(start.begin(), start.end(), param.begin());
    search.run(n, raw->data(), search::Results<double>{param.data(), nullptr, status.data(), nullptr},
               threads);
    return checksum();
  }
  /// One call per query, as a code that searches query by query.
  double one_at_a_time() {
    for (std::size_t i = 0; i < n; ++i) {
      if (!start.empty()) {
        param[2 * i] = start[2 * i];
        param[2 * i + 1] = start[2 * i + 1];
      }
      search.run(1, raw->data() + i * columns,
                 search::Results<double>{param.data() + 2 * i, nullptr, status.data() + i, nullptr}, 1);
    }
    return checksum();
  }
};

/// The raw values of `rows` of `set`, in that order.
std::vector<double> gather_raw(const EvaluationSet& set, const std::vector<std::size_t>& rows) {
  const auto cols = static_cast<std::size_t>(EvaluationSet::raw_columns(set.surface));
  std::vector<double> out;
  out.reserve(rows.size() * cols);
  for (const std::size_t r : rows)
    out.insert(out.end(), set.raw.begin() + static_cast<std::ptrdiff_t>(r * cols),
               set.raw.begin() + static_cast<std::ptrdiff_t>((r + 1) * cols));
  return out;
}

/// `starts`: the set's starts for start+newton:K (starts_near_reference; empty when no method reads them).
void time_set(const EvaluationSet& set, const std::vector<ComparedMethod>& methods,
              const std::vector<search::LocalSearch>& searches, const std::vector<double>& starts,
              const ComparisonOptions& options, SetResult& result, const ProgressLog& log) {
  const std::vector<std::size_t> rows = timing_rows(set, options.timing_queries, options.seed);
  const std::vector<double> raw = gather_raw(set, rows);
  const auto cols = static_cast<std::size_t>(EvaluationSet::raw_columns(set.surface));
  const auto n = static_cast<std::int64_t>(rows.size());
  result.timed = true;
  result.timing_queries = n;
  result.timing_distinct = std::min<std::int64_t>(
      n,
      static_cast<std::int64_t>(std::count_if(set.label_status.begin(), set.label_status.end(), [](Status s) {
        return s == Status::kOk || s == Status::kOutside;
      })));
  std::vector<std::unique_ptr<Runner>> runners;
  std::vector<TimedMethod> timed;
  const int threads = std::max(1, options.timing_threads);
  std::vector<double> start;  // the timed rows' starts, for start+newton:K
  if (!starts.empty()) {
    for (const std::size_t r : rows) start.insert(start.end(), {starts[2 * r], starts[2 * r + 1]});
  }
  for (std::size_t m = 0; m < methods.size(); ++m) {
    runners.push_back(
        std::make_unique<Runner>(searches[m], raw, rows.size(), cols,
                                 methods[m].method.needs_start() ? start : std::vector<double>{}));
    Runner* r = runners.back().get();
    timed.push_back({methods[m].name + " one", "", n, [r] { return r->one_at_a_time(); }});
    timed.push_back({methods[m].name + " batched", "", n, [r] { return r->batched(1); }});
    timed.push_back({methods[m].name + " threads", "", n, [r, threads] { return r->batched(threads); }});
  }
  if (log) log("speed: " + set.name + ": " + std::to_string(timed.size()) + " timed runs");
  const std::vector<Timing> t = time_methods(timed, options.timing_options);
  for (std::size_t m = 0; m < methods.size(); ++m) {
    result.timings.push_back({methods[m].name, t[3 * m], t[3 * m + 1], t[3 * m + 2]});
  }
  // Newton with k fixed steps: a line over k (its intercept the per-query setup, its slope one step).
  std::vector<double> k, batched, one;
  for (int i = 1; i <= 100; ++i) {
    if (const MethodTiming* mt = find_timing(result, "newton:" + std::to_string(i))) {
      k.push_back(i);
      batched.push_back(mt->batched.median_ns);
      one.push_back(mt->one_at_a_time.median_ns);
    }
  }
  if (k.size() >= 2) {
    result.newton_fit = fit_line(k, batched);
    result.newton_fit_one = fit_line(k, one);
  }

  // The first network and "newton" per class of configuration (by the steps "newton" needs).
  const auto first_network = std::find_if(methods.begin(), methods.end(), [](const ComparedMethod& m) {
    return m.method.needs_network() && !m.method.is_hybrid();
  });
  const auto newton = std::find_if(methods.begin(), methods.end(),
                                   [](const ComparedMethod& m) { return m.name == "newton"; });
  if (first_network == methods.end() || newton == methods.end()) return;
  const search::LocalSearch& newton_search = searches[static_cast<std::size_t>(newton - methods.begin())];
  const search::LocalSearch& network_search =
      searches[static_cast<std::size_t>(first_network - methods.begin())];
  std::vector<Status> status(rows.size());
  std::vector<std::int32_t> steps(rows.size());
  std::vector<double> param(2 * rows.size());
  newton_search.run(rows.size(), raw.data(),
                    search::Results<double>{param.data(), nullptr, status.data(), steps.data()});
  std::array<std::vector<std::size_t>, kClassLabels.size()> classes;
  for (std::size_t i = 0; i < rows.size() && i < static_cast<std::size_t>(result.timing_distinct); ++i) {
    const bool converged = status[i] == Status::kOk || status[i] == Status::kOutside;
    std::size_t c = kClassUpper.size();
    for (std::size_t u = 0; converged && u < kClassUpper.size(); ++u) {
      if (steps[i] <= kClassUpper[u]) {
        c = u;
        break;
      }
    }
    classes[c].push_back(i);
  }
  for (std::size_t c = 0; c < classes.size(); ++c) {
    if (classes[c].empty()) continue;
    std::vector<std::size_t> cycled;
    for (std::size_t i = 0; cycled.size() < rows.size(); ++i)
      cycled.push_back(classes[c][i % classes[c].size()]);
    std::vector<double> class_raw;
    class_raw.reserve(cycled.size() * cols);
    for (const std::size_t i : cycled) {
      class_raw.insert(class_raw.end(), raw.begin() + static_cast<std::ptrdiff_t>(i * cols),
                       raw.begin() + static_cast<std::ptrdiff_t>((i + 1) * cols));
    }
    Runner net(network_search, class_raw, cycled.size(), cols),
        plain(newton_search, class_raw, cycled.size(), cols);
    const std::vector<Timing> ct = time_methods({{"network", "", n, [&net] { return net.batched(1); }},
                                                 {"newton", "", n, [&plain] { return plain.batched(1); }}},
                                                options.timing_options);
    result.class_timings.push_back(
        {kClassLabels[c], static_cast<std::int64_t>(classes[c].size()), ct[0].median_ns, ct[1].median_ns});
  }
}

}  // namespace

std::string default_methods(int max_fixed_iterations, bool with_networks) {
  // Hybrids at K = 1, 2, 3 and 5, 8: a block's safeguarded steps stop once all its lanes have converged, so
  // K = 8 costs about K = 4 and reaches rounding-level answers where K = 3 leaves a tail (held-out Gregory).
  const char* const ks[] = {"1", "2", "3", "5", "8"};
  std::string list;
  if (with_networks) {
    list += "network,";
    for (const char* k : ks) list += std::string("network+newton:") + k + ",";
  }
  list += "closed_form,";
  for (const char* k : ks) list += std::string("closed_form+newton:") + k + ",";
  for (int k = 1; k <= max_fixed_iterations; ++k) list += "newton:" + std::to_string(k) + ",";
  return list + "newton";
}

ComparisonResult compare_methods(const std::vector<EvaluationSet>& sets,
                                 const std::vector<EvaluatedNetwork>& networks,
                                 const ComparisonOptions& options, const ProgressLog& log) {
  const auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  CONTACTNN_REQUIRE(!sets.empty(), "no set to evaluate on");
  ComparisonResult result;
  result.surface = sets.front().surface;
  result.networks = networks;
  result.timing_threads = std::max(1, options.timing_threads);
  for (const EvaluationSet& s : sets) {
    CONTACTNN_REQUIRE_AS(FormatError, s.surface == result.surface,
                         "'" << s.source << "' is a " << to_string(s.surface) << " set, '"
                             << sets.front().source << "' a " << to_string(result.surface)
                             << " one: a study is of one surface");
  }
  for (const EvaluatedNetwork& n : networks) {
    CONTACTNN_REQUIRE_AS(FormatError, n.model != nullptr && n.model->surface() == result.surface,
                         "network '" << n.name << "' is not a " << to_string(result.surface) << " network");
  }
  const std::string list =
      with_defaults(options.methods, default_methods(options.max_fixed_iterations, !networks.empty()));
  const std::vector<ComparedMethod> methods = expand_methods(list, networks, options.start_offset);
  const bool any_start = std::any_of(methods.begin(), methods.end(),
                                     [](const ComparedMethod& m) { return m.method.needs_start(); });
  std::vector<search::LocalSearch> searches;
  for (const ComparedMethod& m : methods) {
    searches.emplace_back(result.surface, m.method, options.search,
                          m.network >= 0 ? networks[static_cast<std::size_t>(m.network)].model : nullptr);
    result.methods.push_back(m.name);
  }

  for (std::size_t s = 0; s < sets.size(); ++s) {
    const EvaluationSet& set = sets[s];
    SetResult r;
    r.name = set.name;
    r.source = set.source;
    r.rows = set.rows();
    r.skipped_no_segment = set.skipped_no_segment;
    for (const Status st : set.label_status) ++r.label_status_counts[static_cast<std::size_t>(st)];
    std::vector<std::int32_t> label_iterations;
    for (std::size_t i = 0; i < set.label_iterations.size(); ++i) {
      if (set.label_status[i] == Status::kOk && set.label_iterations[i] >= 0)
        label_iterations.push_back(set.label_iterations[i]);
    }
    r.label_rows_ok = r.label_status_counts[static_cast<std::size_t>(Status::kOk)];
    if (!label_iterations.empty()) r.label_iterations = count_values(label_iterations, kIterationBins);

    // 1. Accuracy: every method on the same world coordinates (start+newton:K from the references moved).
    std::vector<double> starts;  // made once per set, for the accuracy and the timing runs
    if (any_start) starts = starts_near_reference(set, options.start_offset, options.seed);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      say("accuracy: " + set.name + ": " + methods[m].name);
      const Estimates e =
          run_on_set(searches[m], set, 0, methods[m].method.needs_start() ? &starts : nullptr);
      const bool histogram = s == 0 && result.histogram_method.empty() && methods[m].method.needs_network() &&
                             !methods[m].method.is_hybrid();
      MethodErrors errors =
          compare_with_labels(methods[m].name, e, set, options.failure_box_margin, histogram);
      if (methods[m].name == "newton") {
        r.newton_iterations = count_values(errors.converged_iterations, kIterationBins);
        r.newton_failures =
            std::count(errors.converged_iterations.begin(), errors.converged_iterations.end(), -1);
      }
      std::vector<std::int32_t>().swap(errors.converged_iterations);
      if (histogram) {
        result.histogram_method = methods[m].name;
        double range = options.hist_range;
        if (!(range > 0.0)) {
          std::vector<double> abs_errors;
          for (std::size_t c = 0; c < 2; ++c) {
            for (std::size_t i = 0; i < errors.failed.size(); ++i) {
              if (errors.failed[i] == 0) abs_errors.push_back(std::abs(errors.errors[c][i]));
            }
          }
          std::sort(abs_errors.begin(), abs_errors.end());
          range = abs_errors.empty() ? 1.0 : nice_ceil(percentile(abs_errors, 99.9));
        }
        for (std::size_t c = 0; c < 2; ++c) {
          result.histograms[c] =
              make_histogram(errors.errors[c], errors.failed, -range, range, options.hist_bins);
        }
        for (auto& v : errors.errors) std::vector<double>().swap(v);
        std::vector<std::uint8_t>().swap(errors.failed);
      }
      r.errors.push_back(std::move(errors));
    }
    // 2. Speed.
    if (options.timing) time_set(set, methods, searches, starts, options, r, log);
    result.sets.push_back(std::move(r));
  }
  return result;
}

NetworkCostInIterations network_cost_in_iterations(const SetResult& set, const std::string& network_method) {
  NetworkCostInIterations c;
  const MethodTiming* net = find_timing(set, network_method);
  if (net == nullptr || !(set.newton_fit.slope > 0.0) || !(set.newton_fit_one.slope > 0.0)) return c;
  c.available = true;
  c.batched = (net->batched.median_ns - set.newton_fit.intercept) / set.newton_fit.slope;
  c.one_at_a_time = (net->one_at_a_time.median_ns - set.newton_fit_one.intercept) / set.newton_fit_one.slope;
  return c;
}

}  // namespace contactnn::eval
