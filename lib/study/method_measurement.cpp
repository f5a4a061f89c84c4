#include "study/method_measurement.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "eval/report.hpp"
#include "eval/timing.hpp"
#include "search/method.hpp"
#include "study/study_detail.hpp"

namespace contactnn::study {

using detail::split_methods;

namespace {

struct ExpandedMethod {
  std::string name;
  search::Method method;
  int network = -1;
};

std::vector<ExpandedMethod> expand(const std::string& methods, const std::string& network_methods,
                                   const std::vector<const SceneNetwork*>& networks) {
  std::vector<ExpandedMethod> out;
  for (const std::string& m : split_methods(methods)) {
    const search::Method method = search::Method::parse(m);
    out.push_back({method.name(), method, -1});
  }
  for (std::size_t k = 0; k < networks.size(); ++k) {
    for (const std::string& m : split_methods(network_methods)) {
      const search::Method method = search::Method::parse(m);
      out.push_back({method.name() + "[" + networks[k]->name + "]", method, static_cast<int>(k)});
    }
  }
  return out;
}

search::LocalSearch search_of(SurfaceKind surface, const ExpandedMethod& m,
                              const std::vector<const SceneNetwork*>& networks) {
  return search::LocalSearch(
      surface, m.method, {},
      m.network >= 0 ? networks[static_cast<std::size_t>(m.network)]->model.get() : nullptr);
}

}  // namespace

std::vector<MethodMeasurement> measure_methods(const eval::EvaluationSet& set, SurfaceKind surface,
                                               const std::string& methods, const std::string& network_methods,
                                               const std::vector<const SceneNetwork*>& networks,
                                               const SceneStudyOptions& options) {
  const std::vector<ExpandedMethod> expanded = expand(methods, network_methods, networks);
  std::vector<search::LocalSearch> searches;
  std::vector<MethodMeasurement> out;
  const int threads = options.threads;
  for (const ExpandedMethod& m : expanded) {
    searches.push_back(search_of(surface, m, networks));
    MethodMeasurement r;
    r.name = m.name;
    r.method = m.method.name();
    r.network = m.network;
    const eval::Estimates e = eval::run_on_set(searches.back(), set, threads);
    r.errors = eval::compare_with_labels(m.name, e, set, options.failure_box_margin, false);
    std::vector<std::int32_t>().swap(r.errors.converged_iterations);
    r.effective_mean = eval::effective_mean_error(r.errors, surface);
    r.reaches = r.effective_mean <= options.margin * options.target;
    out.push_back(std::move(r));
  }
  // Speed: every method on the same queries (the set's rows with a reference point, cycled up to at least
  // 4096 per pass), batched, 1 thread, round-robin (eval::time_methods).
  std::vector<std::size_t> rows;
  for (std::size_t r = 0;
       r < set.label_status.size() && static_cast<std::int64_t>(rows.size()) < options.timing_queries; ++r) {
    if (set.label_status[r] == Status::kOk || set.label_status[r] == Status::kOutside) rows.push_back(r);
  }
  CONTACTNN_REQUIRE_AS(FormatError, !rows.empty(),
                       "'" << set.source << "' has no row with a reference point to time on");
  const std::size_t distinct = rows.size();
  for (std::size_t i = 0; rows.size() < 4096; ++i) rows.push_back(rows[i % distinct]);
  const auto cols = static_cast<std::size_t>(eval::EvaluationSet::raw_columns(surface));
  std::vector<double> raw;
  raw.reserve(rows.size() * cols);
  for (const std::size_t r : rows) {
    raw.insert(raw.end(), set.raw.begin() + static_cast<std::ptrdiff_t>(r * cols),
               set.raw.begin() + static_cast<std::ptrdiff_t>((r + 1) * cols));
  }
  const std::size_t n = rows.size();
  std::vector<std::vector<double>> param(searches.size(), std::vector<double>(2 * n));
  std::vector<std::vector<Status>> status(searches.size(), std::vector<Status>(n));
  std::vector<eval::TimedMethod> timed;
  for (std::size_t m = 0; m < searches.size(); ++m) {
    timed.push_back({out[m].name, "", static_cast<std::int64_t>(n), [&, m] {
                       searches[m].run(
                           n, raw.data(),
                           search::Results<double>{param[m].data(), nullptr, status[m].data(), nullptr}, 1);
                       double sum = 0.0;
                       for (std::size_t i = 0; i < n; ++i) sum += param[m][2 * i] + 0.5 * param[m][2 * i + 1];
                       return sum;
                     }});
  }
  const std::vector<eval::Timing> timings = eval::time_methods(timed, options.timing);
  // The fastest pass: another process can only slow a pass down (on a busy machine a preempted pass of a fast
  // method read 6 times its time, and the median of 7 passes did not hide it).
  for (std::size_t m = 0; m < out.size(); ++m) out[m].batched_ns = timings[m].min_ns;
  return out;
}

std::vector<int> sizes_that_may_pay(const std::vector<MethodMeasurement>& measured,
                                    const std::vector<SceneNetwork>& untrained,
                                    const SceneStudyOptions& options, std::vector<std::string>* why) {
  if (options.train_networks == TrainNetworks::kNever) {
    if (why) why->push_back("no scene network trained (train_networks = never)");
    return {};
  }
  if (options.train_networks == TrainNetworks::kAlways) return options.sizes;
  const MethodMeasurement* fastest = nullptr;
  for (const MethodMeasurement& m : measured) {
    if (m.network < 0 && m.reaches && (fastest == nullptr || m.batched_ns < fastest->batched_ns))
      fastest = &m;
  }
  std::vector<int> sizes;
  for (const SceneNetwork& n : untrained) {
    const auto it = std::find_if(measured.begin(), measured.end(), [&](const MethodMeasurement& m) {
      return m.name == "network[" + n.name + "]";
    });
    CONTACTNN_REQUIRE(it != measured.end(), "no timing of the untrained network " << n.name);
    if (fastest == nullptr || it->batched_ns < fastest->batched_ns) {
      sizes.push_back(n.hidden);
    } else if (why) {
      char line[240];
      std::snprintf(line, sizeof line,
                    "%s not trained: the network alone takes %.1f ns/query, %s reaches the target in %.1f ns",
                    n.name.substr(0, n.name.size() - std::string("-untrained").size()).c_str(),
                    it->batched_ns, fastest->name.c_str(), fastest->batched_ns);
      why->push_back(line);
    }
  }
  return sizes;
}

search::LocalSearch method_search(SurfaceKind surface, const MethodMeasurement& m,
                                  const std::vector<const SceneNetwork*>& networks) {
  return search_of(surface, ExpandedMethod{m.name, search::Method::parse(m.method), m.network}, networks);
}

}  // namespace contactnn::study
