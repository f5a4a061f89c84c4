// Ranking the compared methods: a method's effective mean error (its failures counted in), the fastest method
// within an accuracy level, and the Pareto front of speed against accuracy. report.md's tables and
// scripts/frontier's (through evaluate-net --frontier, which reads a finished report back) both rank with
// these, so the two cannot disagree.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "eval/method_comparison.hpp"

namespace contactnn::eval {

/// The accuracy levels of the "fastest method at each level" tables, coarsest first.
inline constexpr std::array<double, 7> kAccuracyLevels = {0.1, 0.03, 0.01, 0.003, 1e-3, 1e-4, 1e-8};

/// A method's mean |error| with its failures counted in, each as an error of one domain width: the larger of
/// the two coordinates' (sum |e| + failures x width) / (n + failures). A method that fails on 10% of the
/// rows cannot be more accurate than 0.1 widths, however good its other answers.
[[nodiscard]] double effective_mean_error(const MethodErrors& m, SurfaceKind kind);

/// The timing of `method` on `set`; nullptr when it was not timed.
[[nodiscard]] const MethodTiming* find_timing(const SetResult& set, const std::string& method);

/// The fastest method (1-thread batched median) whose effective_mean_error is at most `level`; nullptr when
/// none reaches it or nothing was timed. Of methods equally fast, the first.
[[nodiscard]] const MethodErrors* fastest_within(const SetResult& set, SurfaceKind kind, double level);

/// One method as a point of the frontier: its 1-thread batched median time and its effective mean error.
struct FrontierPoint {
  std::string method;
  double ns = 0.0;
  double error = 0.0;
};

/// The timed methods of `set`, in its order, as points.
[[nodiscard]] std::vector<FrontierPoint> frontier_points(const SetResult& set, SurfaceKind kind);

/// Indices of the points on the Pareto front, fastest first: the points taken in order of time (then error;
/// ties in their given order), each kept when it is strictly more accurate than every faster one kept.
[[nodiscard]] std::vector<std::size_t> pareto_front(const std::vector<FrontierPoint>& points);

/// A finished report's errors.csv and speed.csv read back (report.hpp writes them): the surface (from the
/// coordinate names), and per set, in file order, each method's errors (the statistics' rows, n, mean_abs,
/// p99_abs, max_abs; the failures and out_of_domain counts) and timings (medians, the batched minimum),
/// timing_threads. Every double reads back to the value the report was computed from. FormatError for a
/// missing file or column, an unknown coordinate, a method without both coordinates or without a speed row.
[[nodiscard]] ComparisonResult read_report_tables(const std::filesystem::path& directory);

/// The ranking as JSON (scripts/frontier reads it): {"surface", "coordinates", "domain_width", "levels":
/// [...], "sets": [{ "name", "rows", "failures_reference", "threads", "methods": [{"method", "mean_abs": [c0,
/// c1], "effective_mean", "p99_abs", "max_abs" (the larger coordinate's), "failures" (the method's),
/// "failures_reference", "out_of_domain", "rows", "one_ns", "batched_ns", "batched_min_ns", "threads_ns",
/// "pareto"}], "fastest": [method or null per level]}]}. Doubles are written to read back exactly (NaN and
/// Infinity as Python's json reads them). Every method must be timed (FormatError otherwise).
[[nodiscard]] std::string ranking_json(const ComparisonResult& result);

}  // namespace contactnn::eval
