#include "eval/histogram.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "eval/error_statistics.hpp"
#include "io/csv.hpp"

namespace contactnn::eval {

double Histogram::edge(int k) const {
  if (k >= bins()) return hi;  // exactly hi, whatever the rounding of bins * w
  return lo + static_cast<double>(k) * ((hi - lo) / static_cast<double>(bins()));
}

int Histogram::bin_of(double x) const {
  const int n = bins();
  if (x < lo) return -1;
  if (x > hi) return n;
  if (x == hi) return n - 1;
  const double w = (hi - lo) / static_cast<double>(n);
  int k = std::clamp(static_cast<int>(std::floor((x - lo) / w)), 0, n - 1);
  // The division can round across an edge; the edges themselves decide.
  while (k > 0 && x < edge(k)) --k;
  while (k < n - 1 && x >= edge(k + 1)) ++k;
  return k;
}

std::int64_t Histogram::total() const {
  std::int64_t sum = underflow + overflow;
  for (const std::int64_t c : counts) sum += c;
  return sum;
}

Histogram make_histogram(std::span<const double> values, std::span<const std::uint8_t> failed, double lo,
                         double hi, int bins) {
  CONTACTNN_REQUIRE(values.size() == failed.size(), "make_histogram: " << values.size() << " values but "
                                                                       << failed.size() << " failure flags");
  CONTACTNN_REQUIRE(
      std::isfinite(lo) && std::isfinite(hi) && lo < hi,
      "make_histogram: range [" << lo << ", " << hi << "] is not a finite interval with lo < hi");
  CONTACTNN_REQUIRE(bins >= 1, "make_histogram: bins = " << bins << ", expected >= 1");
  Histogram h;
  h.lo = lo;
  h.hi = hi;
  h.counts.assign(static_cast<std::size_t>(bins), 0);
  h.excluded = for_each_kept(values, failed, "make_histogram", "value", [&](std::size_t, double x) {
    const int k = h.bin_of(x);
    if (k < 0) {
      ++h.underflow;
    } else if (k >= bins) {
      ++h.overflow;
    } else {
      ++h.counts[static_cast<std::size_t>(k)];
    }
  });
  return h;
}

double nice_ceil(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return 1.0;
  double power = std::pow(10.0, std::floor(std::log10(x)));
  // log10 can round either way near a power of ten.
  if (power > x) power /= 10.0;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= x) return m * power;
  }
  return 10.0 * power;
}

std::string histogram_csv(const Histogram& h) {
  std::string out;
  io::append_csv_row(out, {"bin", "lower_edge", "upper_edge", "count"});
  for (int k = 0; k < h.bins(); ++k) {
    io::append_csv_row(out,
                       {std::to_string(k), io::format_double(h.edge(k)), io::format_double(h.edge(k + 1)),
                        std::to_string(h.counts[static_cast<std::size_t>(k)])});
  }
  io::append_csv_row(out, {"underflow", "-inf", io::format_double(h.lo), std::to_string(h.underflow)});
  io::append_csv_row(out, {"overflow", io::format_double(h.hi), "inf", std::to_string(h.overflow)});
  io::append_csv_row(out, {"excluded", "", "", std::to_string(h.excluded)});
  return out;
}

}  // namespace contactnn::eval
