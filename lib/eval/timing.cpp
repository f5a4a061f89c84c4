#include "eval/timing.hpp"

#include <algorithm>
#include <chrono>

#include "core/error.hpp"

namespace contactnn::eval {

namespace {

// Every checksum ends here: a volatile store the compiler must perform, so each pass's results are used.
volatile double g_sink = 0.0;

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::vector<Timing> time_methods(const std::vector<TimedMethod>& methods, const TimingOptions& options) {
  CONTACTNN_REQUIRE(options.repetitions >= 1,
                    "timing repetitions = " << options.repetitions << ", expected >= 1");
  CONTACTNN_REQUIRE(options.warmup_passes >= 0,
                    "warm-up passes = " << options.warmup_passes << ", expected >= 0");
  for (const TimedMethod& m : methods) {
    CONTACTNN_REQUIRE(m.queries >= 1 && m.run,
                      "timed method '" << m.name << "' has no batch (" << m.queries << " queries)");
  }
  std::vector<Timing> out(methods.size());
  for (std::size_t i = 0; i < methods.size(); ++i) {
    out[i].name = methods[i].name;
    out[i].description = methods[i].description;
    out[i].queries = methods[i].queries;
    out[i].repetitions = options.repetitions;
    for (int w = 0; w < options.warmup_passes; ++w) g_sink = g_sink + methods[i].run();
  }
  using Clock = std::chrono::steady_clock;
  for (int rep = 0; rep < options.repetitions; ++rep) {
    for (std::size_t i = 0; i < methods.size(); ++i) {
      const auto start = Clock::now();
      const double checksum = methods[i].run();
      const auto stop = Clock::now();
      g_sink = g_sink + checksum;
      const double ns = std::chrono::duration<double, std::nano>(stop - start).count();
      out[i].samples_ns.push_back(ns / static_cast<double>(methods[i].queries));
    }
  }
  for (Timing& t : out) {
    t.median_ns = median_of(t.samples_ns);
    t.min_ns = *std::min_element(t.samples_ns.begin(), t.samples_ns.end());
    t.max_ns = *std::max_element(t.samples_ns.begin(), t.samples_ns.end());
  }
  return out;
}

LinearFit fit_line(std::span<const double> x, std::span<const double> y) {
  CONTACTNN_REQUIRE(
      x.size() == y.size() && x.size() >= 2,
      "fit_line: " << x.size() << " x values and " << y.size() << " y values, expected >= 2 of each");
  const auto n = static_cast<double>(x.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  CONTACTNN_REQUIRE(sxx > 0.0, "fit_line: all x values are equal");
  LinearFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ss_res = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (f.intercept + f.slope * x[i]);
    ss_res += r * r;
  }
  f.r_squared = syy > 0.0 ? 1.0 - ss_res / syy : 1.0;
  return f;
}

}  // namespace contactnn::eval
