#include "eval/report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "eval/svg_plot.hpp"
#include "io/csv.hpp"

namespace contactnn::eval {

namespace {

std::string fmt(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}
std::string g4(double x) { return fmt("%.4g", x); }
std::string ns(double x) { return fmt("%.1f", x); }
std::string pct(double part, double whole) { return whole > 0 ? fmt("%.3f %%", 100.0 * part / whole) : "n/a"; }
std::string num(std::int64_t x) { return std::to_string(x); }

const Timing* find_timing(const StudyResult& r, const std::string& name) {
  for (const Timing& t : r.timings) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

const MethodErrors* find_errors(const StudyResult& r, const std::string& name) {
  for (const MethodErrors& m : r.errors) {
    if (m.method.name() == name) return &m;
  }
  return nullptr;
}

std::string ratio_field(const Timing& t, const Timing* base) {
  return base != nullptr && base->median_ns > 0 ? io::format_double(t.median_ns / base->median_ns) : "";
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

std::string errors_csv(const StudyResult& result) {
  std::string out;
  io::append_csv_row(out, {"method", "coordinate", "rows", "n", "failures", "failures_reference", "failures_method",
                           "mean_abs", "std_abs", "mean_signed", "std_signed", "median_abs", "p99_abs", "max_abs",
                           "outside_domain"});
  const auto names = coordinate_names(result.surface);
  for (const MethodErrors& m : result.errors) {
    for (std::size_t c = 0; c < 2; ++c) {
      const ErrorStatistics& s = m.stats[c];
      io::append_csv_row(out, {m.method.name(), std::string(names[c]), num(s.rows), num(s.n), num(s.failures),
                               num(m.failures_reference), num(m.failures_method), io::format_double(s.mean_abs),
                               io::format_double(s.std_abs), io::format_double(s.mean_signed),
                               io::format_double(s.std_signed), io::format_double(s.median_abs),
                               io::format_double(s.p99_abs), io::format_double(s.max_abs), num(m.outside_domain)});
    }
  }
  return out;
}

std::string speed_csv(const StudyResult& result) {
  std::string out;
  io::append_csv_row(out, {"method", "queries", "repetitions", "ns_per_query_median", "ns_per_query_min",
                           "ns_per_query_max", "ratio_to_newton_5", "ratio_to_newton_converged"});
  const Timing* n5 = find_timing(result, "newton_5");
  const Timing* conv = find_timing(result, "newton_converged");
  for (const Timing& t : result.timings) {
    io::append_csv_row(out, {t.name, num(t.queries), std::to_string(t.repetitions), io::format_double(t.median_ns),
                             io::format_double(t.min_ns), io::format_double(t.max_ns), ratio_field(t, n5),
                             ratio_field(t, conv)});
  }
  return out;
}

NetworkCostInIterations network_cost_in_iterations(const StudyResult& result) {
  NetworkCostInIterations c;
  const Timing* net = find_timing(result, "network");
  const Timing* n10 = find_timing(result, "newton_10");
  if (net == nullptr || !(result.newton_fit.slope > 0.0)) return c;
  c.available = true;
  c.equivalent_iterations = (net->median_ns - result.newton_fit.intercept) / result.newton_fit.slope;
  c.per_iteration_units = net->median_ns / result.newton_fit.slope;
  c.newton10_units = n10 != nullptr && n10->median_ns > 0 ? net->median_ns / (n10->median_ns / 10.0) : 0.0;
  if (result.newton_fit_min.slope > 0.0) {
    c.equivalent_iterations_min = (net->min_ns - result.newton_fit_min.intercept) / result.newton_fit_min.slope;
  }
  return c;
}

std::string report_markdown(const StudyResult& r, const RunInfo& info, const StudyOptions& options) {
  const auto names = coordinate_names(r.surface);
  const std::string c0(names[0]), c1(names[1]);
  const bool bilinear = r.surface == SurfaceKind::kBilinear;
  std::ostringstream md;
  md << "# evaluate-net report: " << to_string(r.surface) << " study\n\n";
  md << "- command: `" << info.command_line << "`\n";
  md << "- dataset: `" << info.dataset_path << "`, " << r.rows << " configurations; label statuses:";
  for (int s = 0; s < kStatusCount; ++s) {
    if (r.label_status_counts[static_cast<std::size_t>(s)] > 0) {
      md << " " << to_string(static_cast<Status>(s)) << " " << r.label_status_counts[static_cast<std::size_t>(s)];
    }
  }
  md << "\n- network: `" << info.network_path << "` (" << info.network_summary << ")\n";
  md << "- accuracy placement: "
     << (options.random_placement ? "random similarity per row (seed " + std::to_string(options.seed) + ")"
                                  : "identity (the dataset's normalised frame taken as world coordinates)")
     << "; every method starts from these same raw coordinates\n\n";

  // ---- Accuracy -------------------------------------------------------------------------------------
  const MethodErrors* net = find_errors(r, "network");
  md << "## Accuracy against the Newton labels (Table 1 style)\n\n";
  md << "Error = estimate - label (label: the reference solver of gen-configs). Statistics over the rows that are "
        "not failures; failures are counted, never averaged in.\n\n";
  if (net != nullptr) {
    md << "| network | mean abs " << c0 << " | mean abs " << c1 << " | std abs " << c0 << " | std abs " << c1
       << " | std signed " << c0 << " | std signed " << c1 << " | n | failures |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    md << "| " << info.network_summary << " | " << g4(net->stats[0].mean_abs) << " | " << g4(net->stats[1].mean_abs)
       << " | " << g4(net->stats[0].std_abs) << " | " << g4(net->stats[1].std_abs) << " | "
       << g4(net->stats[0].std_signed) << " | " << g4(net->stats[1].std_signed) << " | " << net->stats[0].n << " | "
       << net->stats[0].failures << " |\n";
    if (!bilinear) {
      md << "| paper Neuro32 | 0.00493 | 0.00758 | 0.00444 | 0.00902 | | | 835906 | |\n";
      md << "| paper Neuro48 | 0.00392 | 0.00479 | 0.00369 | 0.00766 | | | 835906 | |\n";
    }
    md << "\nThe paper's \"standard deviation\" is not defined further; its Table 1 values lie below the mean |e| "
          "for u, which fits the spread of |e| (std abs) rather than of e (std signed); both are given.\n\n";
  }
  md << "### Every method\n\n";
  md << "| method | coordinate | n | failures (reference + method) | mean abs | std abs | median abs | p99 abs | max abs "
        "| outside domain |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const MethodErrors& m : r.errors) {
    for (std::size_t c = 0; c < 2; ++c) {
      const ErrorStatistics& s = m.stats[c];
      md << "| " << m.method.name() << " | " << names[c] << " | " << s.n << " | " << s.failures << " ("
         << m.failures_reference << " + " << m.failures_method << ") | " << g4(s.mean_abs) << " | " << g4(s.std_abs)
         << " | " << g4(s.median_abs) << " | " << g4(s.p99_abs) << " | " << g4(s.max_abs) << " | "
         << m.outside_domain << " |\n";
    }
  }
  md << "\nA method's row fails when the label is not ok, the estimate's status is neither ok nor outside (network: "
        "out_of_domain, degenerate, invalid; Newton to convergence: no_convergence, degenerate, invalid), or the "
        "estimate is non-finite or more than "
     << options.failure_box_margin
     << " domain widths outside the parameter domain. \"outside domain\" counts rows in the statistics whose "
        "estimate lies outside the parameter domain itself. Percentiles interpolate linearly between order "
        "statistics (Hyndman-Fan 7).\n\n";

  md << "### Error histograms of the network (Figs 4 and 10)\n\n";
  for (std::size_t c = 0; c < 2; ++c) {
    const Histogram& h = r.histograms[c];
    md << "![" << names[c] << "](hist_" << names[c] << ".svg)  \n";
    md << "`hist_" << names[c] << ".csv`: " << h.bins() << " bins over [" << g4(h.lo) << ", " << g4(h.hi)
       << "]; below: " << h.underflow << ", above: " << h.overflow << ", failures not plotted: " << h.excluded
       << ". A value on an inner bin edge counts in the bin to its right.\n\n";
  }

  // ---- Paper vs measured ----------------------------------------------------------------------------
  md << "## The paper's statements beside the measurements\n\n";
  md << "| paper | statement | measured here |\n|---|---|---|\n";
  if (net != nullptr) {
    md << "| 5.3.1, Fig 4 | \"the well-trained neural network ... can produce very accurate estimation of local "
          "coordinate values\" (no number given) | mean abs error "
       << c0 << " " << g4(net->stats[0].mean_abs) << ", " << c1 << " " << g4(net->stats[1].mean_abs) << "; p99 "
       << g4(net->stats[0].p99_abs) << " / " << g4(net->stats[1].p99_abs) << "; max " << g4(net->stats[0].max_abs)
       << " / " << g4(net->stats[1].max_abs) << " (domain width " << (bilinear ? 2 : 1) << ") |\n";
  }
  const NetworkCostInIterations cost = network_cost_in_iterations(r);
  if (cost.available) {
    md << "| 5.3.2 | \"The CPU time for the proposed method is on average equal to that of seven iterations in "
          "Newton's method\" | "
       << fmt("%.2f", cost.equivalent_iterations) << " iterations (fitted line, see Speed)"
       << (cost.equivalent_iterations < 0 ? "; negative: the network takes less time than Newton's fitted per-query "
                                            "setup (building the patch) alone"
                                          : "")
       << " |\n";
  }
  md << "| 5.3.2 | \"constant for all patterns of configurations\" | ";
  if (!r.class_timings.empty()) {
    md << "network ns/query per class of configuration (by plain Newton's iteration count):";
    for (const StudyResult::ClassTiming& ct : r.class_timings) md << " " << ct.label << ": " << ns(ct.network_ns) << ";";
    md << " Newton to convergence:";
    for (const StudyResult::ClassTiming& ct : r.class_timings) md << " " << ct.label << ": " << ns(ct.converged_ns) << ";";
    md << " (see Speed) |\n";
  } else {
    md << "not timed; by construction the forward pass has no data-dependent loop or branch |\n";
  }
  const std::int64_t label_over_10 = count_above(r.label_iterations, 10);
  md << "| 5.3.2 | \"more than ten iterations are sometimes required to converge in Newton's method\" | labels: "
     << label_over_10 << " of " << r.label_rows_ok << " ok rows ("
     << pct(static_cast<double>(label_over_10), static_cast<double>(r.label_rows_ok)) << ") needed > 10; plain Newton "
     << "from the centre: ";
  if (!r.newton_converged_iterations.empty()) {
    const std::int64_t plain_over_10 = count_above(r.newton_converged_iterations, 10) + r.newton_converged_failures;
    md << plain_over_10 << " of " << r.rows << " (" << pct(static_cast<double>(plain_over_10), static_cast<double>(r.rows))
       << ") needed > 10 or did not converge |\n";
  } else {
    md << "not run |\n";
  }
  const Timing* t_net = find_timing(r, "network");
  const Timing* t_n5 = find_timing(r, "newton_5");
  if (t_net != nullptr && t_n5 != nullptr) {
    md << "| 6.3.3, Fig 11 | network time / time of Newton with 5 iterations: \"several times faster\" (Gregory "
          "study) | "
       << fmt("%.3f", t_net->median_ns / t_n5->median_ns) << " (" << to_string(r.surface) << ") |\n";
  }
  md << "\n";

  // ---- Speed ----------------------------------------------------------------------------------------
  md << "## Speed (single thread)\n\n";
  if (!r.timed) {
    md << "Not measured (timing = false).\n\n";
  } else {
    md << "Each method runs over the same batch of " << (r.timings.empty() ? 0 : r.timings[0].queries)
       << " dataset configurations, each placed in world coordinates by a random rotation, translation and scale, "
          "and includes its own preprocessing (the network: the Section 4 normalisation; Newton: building its patch "
          "from the world nodes). "
       << options.timing_options.warmup_passes << " warm-up pass(es), then " << options.timing_options.repetitions
       << " timed passes per method, round-robin over the methods; every result is summed into a checksum stored "
          "to a volatile sink. ns/query = pass time / batch size; median, min and max over the passes.\n\n";
    md << "| method | ns/query (median) | min | max | / newton_5 | / newton_converged |\n"
          "|---|---:|---:|---:|---:|---:|\n";
    const Timing* conv = find_timing(r, "newton_converged");
    for (const Timing& t : r.timings) {
      md << "| " << t.name << " | " << ns(t.median_ns) << " | " << ns(t.min_ns) << " | " << ns(t.max_ns) << " | "
         << (t_n5 != nullptr ? fmt("%.3f", t.median_ns / t_n5->median_ns) : "") << " | "
         << (conv != nullptr ? fmt("%.3f", t.median_ns / conv->median_ns) : "") << " |\n";
    }
    md << "\nMethods: ";
    for (const Timing& t : r.timings) md << "`" << t.name << "`: " << t.description << ". ";
    md << "\n\n";
    md << "Newton with k fixed iterations, least-squares line over k = 1.." << options.max_fixed_iterations
       << " (medians): t(k) = " << ns(r.newton_fit.intercept) << " ns + " << ns(r.newton_fit.slope)
       << " ns * k (R^2 = " << fmt("%.4f", r.newton_fit.r_squared) << "); the intercept is the per-query setup "
       << "(building the patch, the call), the slope one iteration.\n\n";
    if (!r.class_timings.empty()) {
      md << "**Cost per class of configuration** (5.3.2: the network's time is constant, Newton's varies). The "
            "batch is split by the iterations plain Newton to convergence needs on each configuration; both "
            "methods are timed on each part as above.\n\n";
      md << "| class | queries | network ns/query | newton_converged ns/query |\n|---|---:|---:|---:|\n";
      for (const StudyResult::ClassTiming& ct : r.class_timings) {
        md << "| " << ct.label << " | " << ct.queries << " | " << ns(ct.network_ns) << " | " << ns(ct.converged_ns)
           << " |\n";
      }
      md << "\n";
    }
    if (cost.available) {
      md << "**The network's cost in Newton iterations.** Primary (the paper's sense, \"equal to that of seven "
            "iterations\"): the k at which the fitted line reaches the network's time, (t_net - intercept) / slope = **"
         << fmt("%.2f", cost.equivalent_iterations) << "**. Also: t_net / slope = " << fmt("%.2f", cost.per_iteration_units)
         << " (the network in units of one marginal iteration); t_net / (t(newton_10) / 10) = "
         << fmt("%.2f", cost.newton10_units) << ". From the minimum times instead of the medians (the least "
            "disturbed pass on a loaded machine; line t(k) = "
         << ns(r.newton_fit_min.intercept) << " ns + " << ns(r.newton_fit_min.slope) << " ns * k): "
         << fmt("%.2f", cost.equivalent_iterations_min) << ".\n\n";
    }
  }

  // ---- Speed-accuracy -------------------------------------------------------------------------------
  md << "## Speed and accuracy together\n\n";
  md << "| method | ns/query | mean abs " << c0 << " | mean abs " << c1 << " | max abs " << c0 << " | max abs " << c1
     << " | method failures |\n|---|---:|---:|---:|---:|---:|---:|\n";
  for (const MethodErrors& m : r.errors) {
    const Timing* t = find_timing(r, m.method.name());
    md << "| " << m.method.name() << " | " << (t != nullptr ? ns(t->median_ns) : "-") << " | "
       << g4(m.stats[0].mean_abs) << " | " << g4(m.stats[1].mean_abs) << " | " << g4(m.stats[0].max_abs) << " | "
       << g4(m.stats[1].max_abs) << " | " << m.failures_method << " |\n";
  }
  md << "\n";

  // ---- Iterations -----------------------------------------------------------------------------------
  md << "## Newton iteration counts\n\n";
  md << "Labels (the dataset's `iterations` column: iterations of the reference solver's start that produced the "
        "label; damped Newton from a 3 x 3 grid of starts), rows with status ok; "
     << label_over_10 << " of " << r.label_rows_ok << " ("
     << pct(static_cast<double>(label_over_10), static_cast<double>(r.label_rows_ok)) << ") needed more than 10:\n\n";
  iteration_table(md, r.label_iterations, r.label_rows_ok);
  if (!r.newton_converged_iterations.empty()) {
    const std::int64_t plain_over_10 = count_above(r.newton_converged_iterations, 10);
    md << "\nPlain Newton from the segment centre to convergence (step <= " << options.newton.converged_tol_param
       << ", at most " << options.newton.converged_max_iterations << "), all rows; " << plain_over_10
       << " converged after more than 10 iterations and " << r.newton_converged_failures
       << " did not converge (or were degenerate):\n\n";
    iteration_table(md, r.newton_converged_iterations, r.rows);
  }
  md << "\n";

  // ---- Domain ---------------------------------------------------------------------------------------
  md << "## Training domain\n\n";
  md << r.network_out_of_domain << " of " << r.rows
     << " rows have a normalised input outside the network's recorded TrainingDomain (status out_of_domain; "
        "counted as failures of the network above, their predictions not averaged in).\n\n";

  // ---- Machine --------------------------------------------------------------------------------------
  md << "## Machine and build\n\n";
  md << "- CPU: " << info.cpu_model << ", " << info.hardware_threads << " hardware threads\n";
  md << "- accuracy part: " << info.accuracy_threads << " OpenMP threads; timing: 1 thread (the calling thread)\n";
  md << "- compiler: " << info.compiler << "\n- build type: " << info.build_type << "\n- flags: `" << info.cxx_flags
     << "`\n\n";
  md << "## Effective configuration\n\n```toml\n" << info.effective_config << "```\n";
  return md.str();
}

void write_report(const std::filesystem::path& directory, const StudyResult& result, const RunInfo& info,
                  const StudyOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  CONTACTNN_REQUIRE_AS(IoError, !ec, "cannot create report directory '" << directory.string() << "': " << ec.message());
  io::write_text_atomically(directory / "errors.csv", errors_csv(result));
  if (result.timed) {
    io::write_text_atomically(directory / "speed.csv", speed_csv(result));
  } else {
    std::filesystem::remove(directory / "speed.csv", ec);  // never leave an older run's timings beside this report
  }
  const auto names = coordinate_names(result.surface);
  for (std::size_t c = 0; c < 2; ++c) {
    const std::string name(names[c]);
    io::write_text_atomically(directory / ("hist_" + name + ".csv"), histogram_csv(result.histograms[c]));
    PlotLabels labels;
    labels.title = "Network " + info.network_summary + ": error in " + name + " (network - Newton), " +
                   std::to_string(result.histograms[c].total()) + " configurations";
    labels.x_label = "error in " + name;
    io::write_text_atomically(directory / ("hist_" + name + ".svg"), histogram_svg(result.histograms[c], labels));
  }
  io::write_text_atomically(directory / "report.md", report_markdown(result, info, options));
}

}  // namespace contactnn::eval
