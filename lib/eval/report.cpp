#include "eval/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "eval/svg_plot.hpp"
#include "io/csv.hpp"

namespace contactnn::eval {

namespace {

std::string g3(double x) { return fmt("%.3g", x); }
std::string g4(double x) { return fmt("%.4g", x); }
std::string ns(double x) { return fmt("%.1f", x); }
std::string pct(double part, double whole) {
  return whole > 0 ? fmt("%.3f %%", 100.0 * part / whole) : "n/a";
}
std::string num(std::int64_t x) { return std::to_string(x); }

const MethodErrors* find_errors(const SetResult& r, const std::string& name) {
  for (const MethodErrors& m : r.errors) {
    if (m.method == name) return &m;
  }
  return nullptr;
}

double inside_fraction(const MethodErrors& m) {
  return m.inside_compared > 0 ? static_cast<double>(m.inside_agree) / static_cast<double>(m.inside_compared)
                               : 0.0;
}

/// Markdown table of an iteration histogram, non-empty bins only.
void iteration_table(std::ostringstream& md, const std::vector<std::int64_t>& counts, std::int64_t total) {
  md << "| iterations | rows | fraction |\n|---:|---:|---:|\n";
  for (std::size_t k = 0; k < counts.size(); ++k) {
    if (counts[k] == 0) continue;
    md << "| " << k << (k + 1 == counts.size() ? "+" : "") << " | " << counts[k] << " | "
       << pct(static_cast<double>(counts[k]), static_cast<double>(total)) << " |\n";
  }
}

std::int64_t count_above(const std::vector<std::int64_t>& counts, std::size_t k) {
  std::int64_t sum = 0;
  for (std::size_t i = k + 1; i < counts.size(); ++i) sum += counts[i];
  return sum;
}

}  // namespace

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        const auto first = line.find_first_not_of(" \t", colon + 1);
        return first == std::string::npos ? "unknown" : line.substr(first);
      }
    }
  }
  return "unknown";
}

std::string errors_csv(const ComparisonResult& result) {
  std::string out;
  io::append_csv_row(out, {"set",
                           "method",
                           "coordinate",
                           "rows",
                           "n",
                           "failures",
                           "failures_reference",
                           "failures_method",
                           "out_of_domain",
                           "mean_abs",
                           "std_abs",
                           "mean_signed",
                           "std_signed",
                           "median_abs",
                           "p99_abs",
                           "max_abs",
                           "outside_domain",
                           "gap_rel_mean_abs",
                           "gap_rel_max_abs",
                           "inside_agreement"});
  const auto names = coordinate_names(result.surface);
  for (const SetResult& set : result.sets) {
    for (const MethodErrors& m : set.errors) {
      for (std::size_t c = 0; c < 2; ++c) {
        const ErrorStatistics& s = m.stats[c];
        io::append_csv_row(out, {set.name,
                                 m.method,
                                 std::string(names[c]),
                                 num(s.rows),
                                 num(s.n),
                                 num(s.failures),
                                 num(m.failures_reference),
                                 num(m.failures_method),
                                 num(m.out_of_domain),
                                 io::format_double(s.mean_abs),
                                 io::format_double(s.std_abs),
                                 io::format_double(s.mean_signed),
                                 io::format_double(s.std_signed),
                                 io::format_double(s.median_abs),
                                 io::format_double(s.p99_abs),
                                 io::format_double(s.max_abs),
                                 num(m.outside_domain),
                                 io::format_double(m.gap_relative.mean_abs),
                                 io::format_double(m.gap_relative.max_abs),
                                 io::format_double(inside_fraction(m))});
      }
    }
  }
  return out;
}

std::string speed_csv(const ComparisonResult& result) {
  std::string out;
  io::append_csv_row(
      out, {"set", "method", "queries", "repetitions", "one_ns", "one_min_ns", "batched_ns", "batched_min_ns",
            "threads", "threads_ns", "threads_min_ns", "batched_per_newton_5"});
  for (const SetResult& set : result.sets) {
    const MethodTiming* n5 = find_timing(set, "newton:5");
    for (const MethodTiming& t : set.timings) {
      io::append_csv_row(
          out, {set.name, t.method, num(t.batched.queries), std::to_string(t.batched.repetitions),
                io::format_double(t.one_at_a_time.median_ns), io::format_double(t.one_at_a_time.min_ns),
                io::format_double(t.batched.median_ns), io::format_double(t.batched.min_ns),
                std::to_string(result.timing_threads), io::format_double(t.batched_threads.median_ns),
                io::format_double(t.batched_threads.min_ns),
                n5 != nullptr && n5->batched.median_ns > 0
                    ? io::format_double(t.batched.median_ns / n5->batched.median_ns)
                    : ""});
    }
  }
  return out;
}

namespace {

/// report.md: the title, the command, the networks and sets, and how errors and failures are counted.
void header_section(std::ostringstream& md, const ComparisonResult& r, const RunInfo& info,
                    const ComparisonOptions& options) {
  md << "# evaluate-net report: " << to_string(r.surface) << "\n\n";
  md << "- command: `" << info.command_line << "`\n";
  for (const EvaluatedNetwork& n : r.networks) md << "- network `" << n.name << "`: " << n.summary << "\n";
  for (const SetResult& s : r.sets) {
    md << "- set `" << s.name << "`: `" << s.source << "`, " << s.rows << " queries; reference statuses:";
    for (int st = 0; st < kStatusCount; ++st) {
      if (s.label_status_counts[static_cast<std::size_t>(st)] > 0) {
        md << " " << to_string(static_cast<Status>(st)) << " "
           << s.label_status_counts[static_cast<std::size_t>(st)];
      }
    }
    if (s.skipped_no_segment > 0)
      md << "; " << s.skipped_no_segment << " slave nodes without a segment left out";
    md << "\n";
  }
  md << "- datasets placed in world coordinates by "
     << (options.random_placement ? "a random similarity per row (seed " + std::to_string(options.seed) + ")"
                                  : "the identity (their own normalised frame)")
     << "; pairs files are world coordinates. Every method starts from the same raw world coordinates and "
        "maps "
        "its answer to the caller's node order.\n";
  if (options.start_offset >= 0.0) {
    md << "- `start+newton:K` starts from each reference point moved " << options.start_offset
       << " (parameter units) in a random direction (seed " << options.seed
       << "), as an FE code's previous time step might give it (the domain centre where the reference has no "
          "point).\n";
  }
  md << "\n";
  md << "Errors are estimate - reference (the reference solver of gen-configs: damped Newton from 3 x 3 "
        "starts, the "
        "nearest in-domain local minimum). A row is a failure, counted and never averaged in, when the "
        "reference has "
        "no point, the method's status is not ok, outside or out_of_domain (a network's estimate outside its "
        "training "
        "domain is still its answer: in the statistics, and counted), or its estimate is non-finite or more "
        "than "
     << options.failure_box_margin
     << " domain widths outside the domain. \"effective\" counts each failure as an error of one domain "
        "width. "
        "Gap error: |g - g_ref| / the segment's longest node distance. Inside agreement: the fraction of "
        "rows whose "
        "estimate lies inside the segment, and whose status is not outside, exactly when the reference's "
        "does.\n\n";
}

/// report.md: per set: every method's accuracy and speed, and the fastest method at each accuracy level.
void set_tables_section(std::ostringstream& md, const ComparisonResult& r, const ComparisonOptions& options) {
  const auto names = coordinate_names(r.surface);
  const std::string c0(names[0]), c1(names[1]);
  const int threads = std::max(1, options.timing_threads);
  for (const SetResult& s : r.sets) {
    md << "## Set `" << s.name << "`: every method\n\n";
    if (s.timed) {
      md << "Speed: ns per query over " << s.timing_queries << " queries (" << s.timing_distinct
         << " distinct rows in random order), medians of " << options.timing_options.repetitions
         << " passes after " << options.timing_options.warmup_passes
         << " warm-up, all methods and modes interleaved round-robin; \"one\": one call per query (1 "
            "thread), "
            "\"batched\": one call for all (lib/search's blocks), on 1 and "
         << threads << " threads. Local coordinates and statuses only (no gap), as the paper times them.\n\n";
    }
    md << "| method | one | batched | batched, " << threads << " threads | mean abs " << c0 << " | mean abs "
       << c1
       << " | p99 abs | max abs | effective mean | gap / size, mean | inside agreement | failures | out of "
          "domain |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const MethodErrors& m : s.errors) {
      const MethodTiming* t = find_timing(s, m.method);
      md << "| " << m.method << " | " << (t ? ns(t->one_at_a_time.median_ns) : "-") << " | "
         << (t ? ns(t->batched.median_ns) : "-") << " | " << (t ? ns(t->batched_threads.median_ns) : "-")
         << " | " << g3(m.stats[0].mean_abs) << " | " << g3(m.stats[1].mean_abs) << " | "
         << g3(std::max(m.stats[0].p99_abs, m.stats[1].p99_abs)) << " | "
         << g3(std::max(m.stats[0].max_abs, m.stats[1].max_abs)) << " | "
         << g3(effective_mean_error(m, r.surface)) << " | " << g3(m.gap_relative.mean_abs) << " | "
         << fmt("%.4f", inside_fraction(m)) << " | " << m.failures_method << " | " << m.out_of_domain
         << " |\n";
    }
    if (s.timed) {
      md << "\n**Fastest method at each accuracy level** (effective mean |error| at most the level; 1-thread "
            "batched "
            "time):\n\n| level | method | ns/query |\n|---:|---|---:|\n";
      for (const double level : kAccuracyLevels) {
        const MethodErrors* m = fastest_within(s, r.surface, level);
        const MethodTiming* t = m ? find_timing(s, m->method) : nullptr;
        md << "| " << g3(level) << " | " << (m ? m->method : std::string("none")) << " | "
           << (t ? ns(t->batched.median_ns) : "-") << " |\n";
      }
    }
    md << "\n";
  }
}

/// report.md: the paper's Table 1 (every network alone, every set) and its error histograms (first network).
void table1_section(std::ostringstream& md, const ComparisonResult& r) {
  const auto names = coordinate_names(r.surface);
  const std::string c0(names[0]), c1(names[1]);
  const bool bilinear = r.surface == SurfaceKind::kBilinear;
  const std::string first_network = r.histogram_method;
  if (!first_network.empty()) {
    md << "## Table 1 style: every network alone\n\n";
    md << "| network | set | mean abs " << c0 << " | mean abs " << c1 << " | std abs " << c0 << " | std abs "
       << c1 << " | std signed " << c0 << " | std signed " << c1 << " | n | failures |\n"
       << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const MethodErrors& method : r.sets.front().errors) {
      if (method.method.rfind("network[", 0) != 0) continue;  // the networks alone, not their hybrids
      for (const SetResult& s : r.sets) {
        if (const MethodErrors* net = find_errors(s, method.method)) {
          md << "| `" << method.method << "` | " << s.name << " | " << g4(net->stats[0].mean_abs) << " | "
             << g4(net->stats[1].mean_abs) << " | " << g4(net->stats[0].std_abs) << " | "
             << g4(net->stats[1].std_abs) << " | " << g4(net->stats[0].std_signed) << " | "
             << g4(net->stats[1].std_signed) << " | " << net->stats[0].n << " | " << net->stats[0].failures
             << " |\n";
        }
      }
    }
    if (!bilinear) {
      md << "| paper Neuro32 | | 0.00493 | 0.00758 | 0.00444 | 0.00902 | | | 835906 | |\n";
      md << "| paper Neuro48 | | 0.00392 | 0.00479 | 0.00369 | 0.00766 | | | 835906 | |\n";
    }
    md << "\nThe paper's \"standard deviation\" is not defined further; its Table 1 values lie below the "
          "mean |e| for "
          "u, which fits the spread of |e| (std abs) rather than of e (std signed); both are given.\n\n";
    md << "### Error histograms (Figs 4 and 10), `" << first_network << "` (the first network), set `"
       << r.sets.front().name << "`\n\n";
    for (std::size_t c = 0; c < 2; ++c) {
      const Histogram& h = r.histograms[c];
      md << "![" << names[c] << "](hist_" << names[c] << ".svg)  \n";
      md << "`hist_" << names[c] << ".csv`: " << h.bins() << " bins over [" << g4(h.lo) << ", " << g4(h.hi)
         << "]; below: " << h.underflow << ", above: " << h.overflow
         << ", failures not plotted: " << h.excluded
         << ". A value on an inner bin edge counts in the bin to its right.\n\n";
    }
  }
}

/// report.md: the paper's statements beside the measurements, first set; Newton's time against its steps.
void paper_statements_section(std::ostringstream& md, const ComparisonResult& r) {
  const auto names = coordinate_names(r.surface);
  const std::string c0(names[0]), c1(names[1]);
  const bool bilinear = r.surface == SurfaceKind::kBilinear;
  const std::string first_network = r.histogram_method;
  const SetResult& first = r.sets.front();
  md << "## The paper's statements beside the measurements (set `" << first.name << "`)\n\n";
  md << "| paper | statement | measured here |\n|---|---|---|\n";
  if (const MethodErrors* net = first_network.empty() ? nullptr : find_errors(first, first_network)) {
    md << "| 5.3.1, Fig 4 | \"the well-trained neural network ... can produce very accurate estimation of "
          "local "
          "coordinate values\" (no number given) | mean abs error "
       << c0 << " " << g4(net->stats[0].mean_abs) << ", " << c1 << " " << g4(net->stats[1].mean_abs)
       << "; p99 " << g4(net->stats[0].p99_abs) << " / " << g4(net->stats[1].p99_abs) << "; max "
       << g4(net->stats[0].max_abs) << " / " << g4(net->stats[1].max_abs) << " (domain width "
       << (bilinear ? 2 : 1) << ") |\n";
  }
  const NetworkCostInIterations cost =
      first_network.empty() ? NetworkCostInIterations{} : network_cost_in_iterations(first, first_network);
  if (cost.available) {
    md << "| 5.3.2 | \"The CPU time for the proposed method is on average equal to that of seven iterations "
          "in "
          "Newton's method\" | one query at a time: "
       << fmt("%.2f", cost.one_at_a_time) << " iterations; batched: " << fmt("%.2f", cost.batched)
       << " (where the line of newton:k reaches the network's time; negative: the network takes less than "
          "Newton's "
          "per-query setup) |\n";
  } else if (!first_network.empty()) {
    // Timings are noisy: with few queries on a loaded machine newton:k may not grow with k. The row stays,
    // saying so.
    md << "| 5.3.2 | \"The CPU time for the proposed method is on average equal to that of seven iterations "
          "in "
          "Newton's method\" | not measured: needs newton:k for two or more k, timed, with the time growing "
          "with k "
          "(raise timing_queries on a loaded machine) |\n";
  }
  md << "| 5.3.2 | \"constant for all patterns of configurations\" | ";
  if (!first.class_timings.empty()) {
    md << "network ns/query per class of configuration (by the steps Newton to convergence needs):";
    for (const auto& ct : first.class_timings) md << " " << ct.label << ": " << ns(ct.network_ns) << ";";
    md << " Newton to convergence:";
    for (const auto& ct : first.class_timings) md << " " << ct.label << ": " << ns(ct.newton_ns) << ";";
    md << " |\n";
  } else {
    md << "not timed; by construction the forward pass has no data-dependent loop or branch |\n";
  }
  if (!first.label_iterations.empty()) {
    const std::int64_t label_over_10 = count_above(first.label_iterations, 10);
    md << "| 5.3.2 | \"more than ten iterations are sometimes required to converge in Newton's method\" | "
          "labels: "
       << label_over_10 << " of " << first.label_rows_ok << " ok rows ("
       << pct(static_cast<double>(label_over_10), static_cast<double>(first.label_rows_ok))
       << ") needed > 10";
    if (!first.newton_iterations.empty()) {
      const std::int64_t plain = count_above(first.newton_iterations, 10) + first.newton_failures;
      md << "; plain Newton from the centre: " << plain << " of " << first.rows << " ("
         << pct(static_cast<double>(plain), static_cast<double>(first.rows))
         << ") needed > 10 or did not converge";
    }
    md << " |\n";
  }
  const MethodTiming* t_net = first_network.empty() ? nullptr : find_timing(first, first_network);
  const MethodTiming* t_n5 = find_timing(first, "newton:5");
  if (t_net != nullptr && t_n5 != nullptr) {
    md << "| 6.3.3, Fig 11 | network time / time of Newton with 5 iterations: \"several times faster\" "
          "(Gregory) | "
       << "one at a time " << fmt("%.3f", t_net->one_at_a_time.median_ns / t_n5->one_at_a_time.median_ns)
       << ", batched " << fmt("%.3f", t_net->batched.median_ns / t_n5->batched.median_ns) << " |\n";
  }
  md << "\n";
  if (first.timed && first.newton_fit.slope > 0.0) {
    md << "Newton with k fixed steps, least-squares line over k (medians): batched t(k) = "
       << ns(first.newton_fit.intercept) << " ns + " << ns(first.newton_fit.slope)
       << " ns * k (R^2 = " << fmt("%.4f", first.newton_fit.r_squared)
       << "); one at a time t(k) = " << ns(first.newton_fit_one.intercept) << " ns + "
       << ns(first.newton_fit_one.slope)
       << " ns * k. The intercept is the per-query setup (the call, reading the nodes, building the patch), "
          "the slope "
          "one step.\n\n";
  }
  if (!first.class_timings.empty()) {
    md << "| class | queries | network ns/query | newton ns/query |\n|---|---:|---:|---:|\n";
    for (const auto& ct : first.class_timings) {
      md << "| " << ct.label << " | " << ct.queries << " | " << ns(ct.network_ns) << " | " << ns(ct.newton_ns)
         << " |\n";
    }
    md << "\n";
  }
}

/// report.md: newton iteration counts of the labels and of plain Newton, first set.
void iteration_counts_section(std::ostringstream& md, const ComparisonResult& r,
                              const ComparisonOptions& options) {
  const SetResult& first = r.sets.front();
  if (!first.label_iterations.empty()) {
    md << "## Newton iteration counts (set `" << first.name << "`)\n\n";
    md << "Labels (iterations of the reference solver's start that produced the label), rows with status "
          "ok:\n\n";
    iteration_table(md, first.label_iterations, first.label_rows_ok);
    md << "\n";
  }
  if (!first.newton_iterations.empty()) {
    md << "Plain Newton from the segment centre to convergence (step <= " << options.search.tol_param
       << ", at most " << options.search.max_iterations << "), converged rows; " << first.newton_failures
       << " did not converge (or were degenerate):\n\n";
    iteration_table(md, first.newton_iterations, first.rows);
    md << "\n";
  }
}

/// report.md: the machine, the build and the effective configuration.
void machine_section(std::ostringstream& md, const RunInfo& info, const ComparisonOptions& options) {
  const int threads = std::max(1, options.timing_threads);
  md << "## Machine and build\n\n";
  md << "- CPU: " << info.cpu_model << ", " << info.hardware_threads << " hardware threads\n";
  md << "- accuracy part: " << info.accuracy_threads << " OpenMP threads; timing: 1 and " << threads
     << " threads as stated\n";
  md << "- compiler: " << info.compiler << "\n- build type: " << info.build_type << "\n- flags: `"
     << info.cxx_flags << "`\n\n";
  md << "## Effective configuration\n\n```toml\n" << info.effective_config << "```\n";
}

}  // namespace

std::string comparison_markdown(const ComparisonResult& r, const RunInfo& info,
                                const ComparisonOptions& options) {
  std::ostringstream md;
  header_section(md, r, info, options);
  set_tables_section(md, r, options);
  table1_section(md, r);
  paper_statements_section(md, r);
  iteration_counts_section(md, r, options);
  machine_section(md, info, options);
  return md.str();
}

void write_report(const std::filesystem::path& directory, const ComparisonResult& result, const RunInfo& info,
                  const ComparisonOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  CONTACTNN_REQUIRE_AS(IoError, !ec,
                       "cannot create report directory '" << directory.string() << "': " << ec.message());
  io::write_text_atomically(directory / "errors.csv", errors_csv(result));
  const bool timed =
      std::any_of(result.sets.begin(), result.sets.end(), [](const SetResult& s) { return s.timed; });
  if (timed) io::write_text_atomically(directory / "speed.csv", speed_csv(result));
  if (!result.histogram_method.empty()) {
    const auto names = coordinate_names(result.surface);
    for (std::size_t c = 0; c < 2; ++c) {
      const std::string name(names[c]);
      io::write_text_atomically(directory / ("hist_" + name + ".csv"), histogram_csv(result.histograms[c]));
      PlotLabels labels;
      labels.title = result.histogram_method + ": error in " + name + " (network - reference), " +
                     std::to_string(result.histograms[c].total()) + " configurations";
      labels.x_label = "error in " + name;
      io::write_text_atomically(directory / ("hist_" + name + ".svg"),
                                histogram_svg(result.histograms[c], labels));
    }
  }
  io::write_text_atomically(directory / "report.md", comparison_markdown(result, info, options));
}

}  // namespace contactnn::eval
