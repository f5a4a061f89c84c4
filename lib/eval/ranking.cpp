#include "eval/ranking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/error.hpp"
#include "io/csv.hpp"

namespace contactnn::eval {

double effective_mean_error(const MethodErrors& m, SurfaceKind kind) {
  const ParamDomain d = param_domain(kind);
  const double width = d.hi - d.lo;
  double worst = 0.0;
  for (const ErrorStatistics& s : m.stats) {
    const double n = static_cast<double>(s.n), failures = static_cast<double>(m.failures_method);
    if (n + failures <= 0.0) continue;
    worst = std::max(worst, (s.mean_abs * n + failures * width) / (n + failures));
  }
  return worst;
}

const MethodTiming* find_timing(const SetResult& set, const std::string& method) {
  for (const MethodTiming& t : set.timings) {
    if (t.method == method) return &t;
  }
  return nullptr;
}

const MethodErrors* fastest_within(const SetResult& set, SurfaceKind kind, double level) {
  const MethodErrors* best = nullptr;
  double best_ns = 0.0;
  for (const MethodErrors& m : set.errors) {
    const MethodTiming* t = find_timing(set, m.method);
    if (t == nullptr || !(effective_mean_error(m, kind) <= level)) continue;
    if (best == nullptr || t->batched.median_ns < best_ns) {
      best = &m;
      best_ns = t->batched.median_ns;
    }
  }
  return best;
}

std::vector<FrontierPoint> frontier_points(const SetResult& set, SurfaceKind kind) {
  std::vector<FrontierPoint> points;
  for (const MethodErrors& m : set.errors) {
    if (const MethodTiming* t = find_timing(set, m.method)) {
      points.push_back({m.method, t->batched.median_ns, effective_mean_error(m, kind)});
    }
  }
  return points;
}

std::vector<std::size_t> pareto_front(const std::vector<FrontierPoint>& points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (points[a].ns != points[b].ns) return points[a].ns < points[b].ns;
    return points[a].error < points[b].error;
  });
  std::vector<std::size_t> front;
  for (const std::size_t i : order) {
    if (front.empty() || points[i].error < points[front.back()].error) front.push_back(i);
  }
  return front;
}

namespace {

/// The set named `name` in `result`, appended when new (file order kept).
SetResult& set_named(ComparisonResult& result, const std::string& name) {
  for (SetResult& s : result.sets) {
    if (s.name == name) return s;
  }
  result.sets.emplace_back().name = name;
  return result.sets.back();
}

void read_errors(const std::filesystem::path& path, ComparisonResult& result) {
  const io::CsvTable t = io::read_csv(path);
  const std::size_t set = t.column("set"), method = t.column("method"), coordinate = t.column("coordinate"),
                    rows = t.column("rows"), n = t.column("n"), reference = t.column("failures_reference"),
                    failures = t.column("failures_method"), out = t.column("out_of_domain"),
                    mean = t.column("mean_abs"), p99 = t.column("p99_abs"), max = t.column("max_abs");
  CONTACTNN_REQUIRE_AS(FormatError, !t.rows.empty(), "'" << path.string() << "' has no rows");
  const std::string first = t.rows.front()[coordinate];
  result.surface = first == "u" || first == "v" ? SurfaceKind::kGregory : SurfaceKind::kBilinear;
  const auto names = coordinate_names(result.surface);
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const std::vector<std::string>& row = t.rows[r];
    const std::size_t c = row[coordinate] == names[0] ? 0 : row[coordinate] == names[1] ? 1 : 2;
    CONTACTNN_REQUIRE_AS(FormatError, c < 2,
                         "'" << path.string() << "':" << t.line_numbers[r] << ": coordinate '"
                             << row[coordinate] << "' is not one of a " << to_string(result.surface)
                             << " report's");
    SetResult& s = set_named(result, row[set]);
    auto m = std::find_if(s.errors.begin(), s.errors.end(),
                          [&](const MethodErrors& e) { return e.method == row[method]; });
    if (m == s.errors.end()) {
      s.errors.emplace_back().method = row[method];
      m = s.errors.end() - 1;
    }
    ErrorStatistics& st = m->stats[c];
    st.rows = static_cast<std::int64_t>(t.number(r, rows));
    st.n = static_cast<std::int64_t>(t.number(r, n));
    st.mean_abs = t.number(r, mean);
    st.p99_abs = t.number(r, p99);
    st.max_abs = t.number(r, max);
    m->rows = st.rows;
    m->failures_reference = static_cast<std::int64_t>(t.number(r, reference));
    m->failures_method = static_cast<std::int64_t>(t.number(r, failures));
    m->out_of_domain = static_cast<std::int64_t>(t.number(r, out));
  }
}

void read_speed(const std::filesystem::path& path, ComparisonResult& result) {
  const io::CsvTable t = io::read_csv(path);
  const std::size_t set = t.column("set"), method = t.column("method"), one = t.column("one_ns"),
                    batched = t.column("batched_ns"), batched_min = t.column("batched_min_ns"),
                    threads = t.column("threads"), threads_ns = t.column("threads_ns");
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    SetResult& s = set_named(result, t.rows[r][set]);
    MethodTiming& timing = s.timings.emplace_back();
    timing.method = t.rows[r][method];
    timing.one_at_a_time.median_ns = t.number(r, one);
    timing.batched.median_ns = t.number(r, batched);
    timing.batched.min_ns = t.number(r, batched_min);
    timing.batched_threads.median_ns = t.number(r, threads_ns);
    result.timing_threads = static_cast<int>(t.number(r, threads));
    s.timed = true;
  }
}

}  // namespace

ComparisonResult read_report_tables(const std::filesystem::path& directory) {
  ComparisonResult result;
  read_errors(directory / "errors.csv", result);
  read_speed(directory / "speed.csv", result);
  const auto names = coordinate_names(result.surface);
  for (const SetResult& s : result.sets) {
    CONTACTNN_REQUIRE_AS(
        FormatError, !s.errors.empty(),
        "'" << (directory / "speed.csv").string() << "': set '" << s.name << "' is not in errors.csv");
    for (const MethodErrors& m : s.errors) {
      CONTACTNN_REQUIRE_AS(FormatError, m.stats[0].rows > 0 && m.stats[1].rows > 0,
                           "'" << (directory / "errors.csv").string() << "': set '" << s.name << "' method '"
                               << m.method << "' lacks its " << names[0] << " or " << names[1] << " row");
      CONTACTNN_REQUIRE_AS(FormatError, find_timing(s, m.method) != nullptr,
                           "'" << (directory / "speed.csv").string() << "': no row for set '" << s.name
                               << "' method '" << m.method << "' (was timing off?)");
    }
  }
  return result;
}

namespace {

/// A double that Python's json module reads back to the same value.
std::string json_number(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  return io::format_double(x);
}

/// A JSON string: quotes, backslashes and control characters escaped.
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string method_json(const MethodErrors& m, const MethodTiming& t, SurfaceKind kind, bool pareto) {
  const auto& [s0, s1] = m.stats;
  std::string out = "{\"method\": " + json_string(m.method);
  out += ", \"mean_abs\": [" + json_number(s0.mean_abs) + ", " + json_number(s1.mean_abs) + "]";
  out += ", \"effective_mean\": " + json_number(effective_mean_error(m, kind));
  out += ", \"p99_abs\": " + json_number(std::max(s0.p99_abs, s1.p99_abs));
  out += ", \"max_abs\": " + json_number(std::max(s0.max_abs, s1.max_abs));
  out += ", \"failures\": " + std::to_string(m.failures_method);
  out += ", \"failures_reference\": " + std::to_string(m.failures_reference);
  out += ", \"out_of_domain\": " + std::to_string(m.out_of_domain);
  out += ", \"rows\": " + std::to_string(s0.rows);
  out += ", \"one_ns\": " + json_number(t.one_at_a_time.median_ns);
  out += ", \"batched_ns\": " + json_number(t.batched.median_ns);
  out += ", \"batched_min_ns\": " + json_number(t.batched.min_ns);
  out += ", \"threads_ns\": " + json_number(t.batched_threads.median_ns);
  return out + ", \"pareto\": " + (pareto ? "true" : "false") + "}";
}

std::string set_json(const SetResult& s, SurfaceKind kind, int threads) {
  std::vector<bool> on_front(s.errors.size(), false);
  for (const std::size_t i : pareto_front(frontier_points(s, kind))) on_front[i] = true;
  std::string out = "{\"name\": " + json_string(s.name) +
                    ", \"rows\": " + std::to_string(s.errors.front().stats[0].rows) +
                    ", \"failures_reference\": " + std::to_string(s.errors.front().failures_reference) +
                    ", \"threads\": " + std::to_string(threads) + ",\n   \"methods\": [";
  for (std::size_t i = 0; i < s.errors.size(); ++i) {
    const MethodTiming* t = find_timing(s, s.errors[i].method);
    CONTACTNN_REQUIRE_AS(FormatError, t != nullptr,
                         "set '" << s.name << "' method '" << s.errors[i].method << "' was not timed");
    out += (i > 0 ? ",\n    " : "\n    ") + method_json(s.errors[i], *t, kind, on_front[i]);
  }
  out += "],\n   \"fastest\": [";
  for (std::size_t k = 0; k < kAccuracyLevels.size(); ++k) {
    const MethodErrors* m = fastest_within(s, kind, kAccuracyLevels[k]);
    out += (k > 0 ? ", " : "") + (m != nullptr ? json_string(m->method) : std::string("null"));
  }
  return out + "]}";
}

}  // namespace

std::string ranking_json(const ComparisonResult& result) {
  const ParamDomain d = param_domain(result.surface);
  std::string out = "{\"surface\": " + json_string(to_string(result.surface)) + ", \"coordinates\": [" +
                    json_string(coordinate_names(result.surface)[0]) + ", " +
                    json_string(coordinate_names(result.surface)[1]) +
                    "], \"domain_width\": " + json_number(d.hi - d.lo) + ",\n \"levels\": [";
  for (std::size_t k = 0; k < kAccuracyLevels.size(); ++k) {
    out += (k > 0 ? ", " : "") + json_number(kAccuracyLevels[k]);
  }
  out += "],\n \"sets\": [";
  for (std::size_t i = 0; i < result.sets.size(); ++i) {
    out += (i > 0 ? ",\n  " : "\n  ") + set_json(result.sets[i], result.surface, result.timing_threads);
  }
  return out + "]}\n";
}

}  // namespace contactnn::eval
