#include "eval/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/error.hpp"

namespace contactnn::eval {

namespace {

// Layout in SVG user units: the plot area sits inside the margins, which hold the tick labels, axis
// labels and title.
constexpr double kWidth = 760.0;
constexpr double kHeight = 460.0;
constexpr double kLeft = 90.0;
constexpr double kRight = 30.0;
constexpr double kTop = 50.0;
constexpr double kBottom = 90.0;

std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", x);
  return buffer;
}

std::string count_text(std::int64_t count) { return std::to_string(count); }

}  // namespace

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

/// The document's opening: the XML declaration, the <svg> element, its title, a white page and the title
/// text.
std::string svg_opening(const std::string& title) {
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + number(kWidth) +
       "\" height=\"" + number(kHeight) + "\" viewBox=\"0 0 " + number(kWidth) + " " + number(kHeight) +
       "\">\n";
  s += "  <title>" + xml_escape(title) + "</title>\n";
  s += "  <rect x=\"0\" y=\"0\" width=\"" + number(kWidth) + "\" height=\"" + number(kHeight) +
       "\" fill=\"white\"/>\n";
  s += "  <text x=\"" + number(kWidth / 2) +
       "\" y=\"28\" text-anchor=\"middle\" font-family=\"sans-serif\" "
       "font-size=\"15\">" +
       xml_escape(title) + "</text>\n";
  return s;
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target) {
  CONTACTNN_REQUIRE(std::isfinite(lo) && std::isfinite(hi) && lo < hi,
                    "nice_ticks: bad range [" << lo << ", " << hi << "]");
  const double step = nice_ceil((hi - lo) / std::max(target, 1));
  std::vector<double> ticks;
  const double first = std::ceil(lo / step - 1e-9);
  const double last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last; k += 1.0) {
    const double t = k * step;
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);  // no "-0"
  }
  return ticks;
}

std::string tick_label(double value, double step) {
  char buffer[32];
  for (int digits = 1; digits <= 6; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    if (std::abs(std::strtod(buffer, nullptr) - value) <= 1e-9 * std::abs(step)) return buffer;
  }
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string histogram_svg(const Histogram& h, const PlotLabels& labels) {
  CONTACTNN_REQUIRE(h.bins() >= 1 && h.lo < h.hi, "histogram_svg: empty histogram");
  const double plot_w = kWidth - kLeft - kRight;
  const double plot_h = kHeight - kTop - kBottom;
  // At least 5 on the count axis, so that its ticks are whole numbers.
  const std::int64_t max_count =
      std::max<std::int64_t>(5, *std::max_element(h.counts.begin(), h.counts.end()));
  std::vector<double> y_ticks = nice_ticks(0.0, static_cast<double>(max_count), 5);
  const double y_step = y_ticks.size() >= 2 ? y_ticks[1] - y_ticks[0] : 1.0;
  // The y axis ends at the first tick at or above the largest count, and that tick is labelled.
  if (y_ticks.back() < static_cast<double>(max_count)) y_ticks.push_back(y_ticks.back() + y_step);
  const double y_top = y_ticks.back();
  const auto x_of = [&](double x) { return kLeft + (x - h.lo) / (h.hi - h.lo) * plot_w; };
  const auto y_of = [&](double c) { return kTop + plot_h - c / y_top * plot_h; };

  std::string s = svg_opening(labels.title);

  // Bars.
  s += "  <g fill=\"#4a74b0\" stroke=\"none\">\n";
  for (int k = 0; k < h.bins(); ++k) {
    const std::int64_t c = h.counts[static_cast<std::size_t>(k)];
    if (c == 0) continue;
    const double x0 = x_of(h.edge(k));
    const double x1 = x_of(h.edge(k + 1));
    const double y = y_of(static_cast<double>(c));
    s += "    <rect x=\"" + number(x0) + "\" y=\"" + number(y) + "\" width=\"" +
         number(std::max(x1 - x0, 0.5)) + "\" height=\"" + number(kTop + plot_h - y) + "\"/>\n";
  }
  s += "  </g>\n";

  // Axes, ticks and tick labels.
  s += "  <g stroke=\"black\" stroke-width=\"1\" fill=\"none\">\n";
  s += "    <line x1=\"" + number(kLeft) + "\" y1=\"" + number(kTop + plot_h) + "\" x2=\"" +
       number(kLeft + plot_w) + "\" y2=\"" + number(kTop + plot_h) + "\"/>\n";
  s += "    <line x1=\"" + number(kLeft) + "\" y1=\"" + number(kTop) + "\" x2=\"" + number(kLeft) +
       "\" y2=\"" + number(kTop + plot_h) + "\"/>\n";
  const std::vector<double> x_ticks = nice_ticks(h.lo, h.hi, 8);
  for (const double t : x_ticks) {
    s += "    <line x1=\"" + number(x_of(t)) + "\" y1=\"" + number(kTop + plot_h) + "\" x2=\"" +
         number(x_of(t)) + "\" y2=\"" + number(kTop + plot_h + 5) + "\"/>\n";
  }
  for (const double t : y_ticks) {
    s += "    <line x1=\"" + number(kLeft - 5) + "\" y1=\"" + number(y_of(t)) + "\" x2=\"" + number(kLeft) +
         "\" y2=\"" + number(y_of(t)) + "\"/>\n";
  }
  s += "  </g>\n";
  s += "  <g font-family=\"sans-serif\" font-size=\"11\" fill=\"black\">\n";
  const double x_step = x_ticks.size() >= 2 ? x_ticks[1] - x_ticks[0] : h.hi - h.lo;
  for (const double t : x_ticks) {
    s += "    <text x=\"" + number(x_of(t)) + "\" y=\"" + number(kTop + plot_h + 18) +
         "\" text-anchor=\"middle\">" + xml_escape(tick_label(t, x_step)) + "</text>\n";
  }
  for (const double t : y_ticks) {
    // Counts are whole numbers: written in full, not in exponent form.
    const std::string label = y_step >= 1.0 ? std::to_string(std::llround(t)) : tick_label(t, y_step);
    s += "    <text x=\"" + number(kLeft - 8) + "\" y=\"" + number(y_of(t) + 4) + "\" text-anchor=\"end\">" +
         xml_escape(label) + "</text>\n";
  }
  s += "  </g>\n";

  // Axis labels and the outlier footnote.
  s += "  <text x=\"" + number(kLeft + plot_w / 2) + "\" y=\"" + number(kTop + plot_h + 42) +
       "\" text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"13\">" + xml_escape(labels.x_label) +
       "</text>\n";
  s += "  <text x=\"20\" y=\"" + number(kTop + plot_h / 2) +
       "\" text-anchor=\"middle\" font-family=\"sans-serif\" "
       "font-size=\"13\" transform=\"rotate(-90 20 " +
       number(kTop + plot_h / 2) + ")\">" + xml_escape(labels.y_label) + "</text>\n";
  s += "  <text x=\"" + number(kLeft) + "\" y=\"" + number(kHeight - 14) +
       "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#444444\">" +
       xml_escape(std::to_string(h.bins()) + " bins over [" + tick_label(h.lo, x_step) + ", " +
                  tick_label(h.hi, x_step) + "]; outside the plot: " + count_text(h.underflow) + " below, " +
                  count_text(h.overflow) + " above; " + count_text(h.excluded) + " failures not plotted") +
       "</text>\n";
  s += "</svg>\n";
  return s;
}

namespace {

/// A line plot's frame: the data ranges (y transformed when log) and the plot area, with the maps to it.
struct LineFrame {
  double x_lo = 0.0, x_hi = 1.0, y_lo = 0.0, y_hi = 1.0;
  double plot_w = kWidth - kLeft - kRight - 150.0;  // the legend on the right
  double plot_h = kHeight - kTop - kBottom;
  [[nodiscard]] double x_of(double v) const { return kLeft + (v - x_lo) / (x_hi - x_lo) * plot_w; }
  [[nodiscard]] double y_of(double v) const { return kTop + plot_h - (v - y_lo) / (y_hi - y_lo) * plot_h; }
};

bool drawable(double y, bool log_y) { return std::isfinite(y) && (!log_y || y > 0.0); }
double transformed(double y, bool log_y) { return log_y ? std::log10(y) : y; }

/// The ranges: x's over its values, y's over the drawable values (whole decades when log; from 0 at most
/// otherwise); a range of no width made one wide.
LineFrame line_frame(const std::vector<double>& x, const std::vector<LineSeries>& series, bool log_y) {
  LineFrame f;
  if (!x.empty()) {
    f.x_lo = *std::min_element(x.begin(), x.end());
    f.x_hi = *std::max_element(x.begin(), x.end());
  }
  if (!(f.x_hi > f.x_lo)) f.x_hi = f.x_lo + 1.0;
  bool any = false;
  for (const LineSeries& l : series) {
    for (double y : l.y) {
      if (!drawable(y, log_y)) continue;
      const double t = transformed(y, log_y);
      f.y_lo = any ? std::min(f.y_lo, t) : t;
      f.y_hi = any ? std::max(f.y_hi, t) : t;
      any = true;
    }
  }
  if (log_y) {
    f.y_lo = std::floor(f.y_lo);
    f.y_hi = std::ceil(f.y_hi);
  } else {
    f.y_lo = std::min(f.y_lo, 0.0);
  }
  if (!(f.y_hi > f.y_lo)) f.y_hi = f.y_lo + 1.0;
  return f;
}

/// The axes, their ticks and tick labels, and the axis labels.
std::string line_plot_axes(const LineFrame& f, const PlotLabels& labels, bool log_y) {
  std::string s;
  s += "  <g stroke=\"black\" stroke-width=\"1\" fill=\"none\">\n";
  s += "    <line x1=\"" + number(kLeft) + "\" y1=\"" + number(kTop + f.plot_h) + "\" x2=\"" +
       number(kLeft + f.plot_w) + "\" y2=\"" + number(kTop + f.plot_h) + "\"/>\n";
  s += "    <line x1=\"" + number(kLeft) + "\" y1=\"" + number(kTop) + "\" x2=\"" + number(kLeft) +
       "\" y2=\"" + number(kTop + f.plot_h) + "\"/>\n";
  s += "  </g>\n";
  const std::vector<double> x_ticks = nice_ticks(f.x_lo, f.x_hi, 8);
  std::vector<double> y_ticks;
  if (log_y) {
    for (double d = f.y_lo; d <= f.y_hi + 1e-9; d += std::max(1.0, std::ceil((f.y_hi - f.y_lo) / 8.0)))
      y_ticks.push_back(d);
  } else {
    y_ticks = nice_ticks(f.y_lo, f.y_hi, 6);
  }
  const double x_step = x_ticks.size() >= 2 ? x_ticks[1] - x_ticks[0] : f.x_hi - f.x_lo;
  const double y_step = y_ticks.size() >= 2 ? y_ticks[1] - y_ticks[0] : f.y_hi - f.y_lo;
  s += "  <g font-family=\"sans-serif\" font-size=\"11\" fill=\"black\">\n";
  for (const double t : x_ticks) {
    s += "    <text x=\"" + number(f.x_of(t)) + "\" y=\"" + number(kTop + f.plot_h + 18) +
         "\" text-anchor=\"middle\">" + xml_escape(tick_label(t, x_step)) + "</text>\n";
  }
  for (const double t : y_ticks) {
    const std::string label =
        log_y ? "1e" + std::to_string(static_cast<int>(std::lround(t))) : tick_label(t, y_step);
    s += "    <text x=\"" + number(kLeft - 8) + "\" y=\"" + number(f.y_of(t) + 4) +
         "\" text-anchor=\"end\">" + xml_escape(label) + "</text>\n";
  }
  s += "    <text x=\"" + number(kLeft + f.plot_w / 2) + "\" y=\"" + number(kHeight - 40) +
       "\" text-anchor=\"middle\" font-size=\"13\">" + xml_escape(labels.x_label) + "</text>\n";
  s += "    <text x=\"20\" y=\"" + number(kTop + f.plot_h / 2) +
       "\" text-anchor=\"middle\" font-size=\"13\" "
       "transform=\"rotate(-90 20 " +
       number(kTop + f.plot_h / 2) + ")\">" + xml_escape(labels.y_label + (log_y ? " (log scale)" : "")) +
       "</text>\n";
  s += "  </g>\n";
  return s;
}

/// Series k's line (a gap where a value cannot be drawn) and its legend entry.
std::string line_plot_series(const LineFrame& f, const std::vector<double>& x, const LineSeries& line,
                             std::size_t k, bool log_y) {
  static const char* const kColours[] = {"#4a74b0", "#d9742b", "#3a9a4a", "#b03a3a", "#7a5ab0",
                                         "#7a6a4a", "#c05aa0", "#5a5a5a", "#a0a030", "#30a0a0"};
  const char* colour = kColours[k % (sizeof kColours / sizeof kColours[0])];
  std::string s, points;
  const auto flush = [&]() {
    if (!points.empty()) {
      s += "  <polyline fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"1.5\" points=\"" +
           points + "\"/>\n";
    }
    points.clear();
  };
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double y = line.y[i];
    if (!drawable(y, log_y) || !std::isfinite(x[i])) {
      flush();
      continue;
    }
    points +=
        (points.empty() ? "" : " ") + number(f.x_of(x[i])) + "," + number(f.y_of(transformed(y, log_y)));
  }
  flush();
  const double ly = kTop + 12.0 + 18.0 * static_cast<double>(k);
  s += "  <line x1=\"" + number(kLeft + f.plot_w + 15) + "\" y1=\"" + number(ly - 4) + "\" x2=\"" +
       number(kLeft + f.plot_w + 35) + "\" y2=\"" + number(ly - 4) + "\" stroke=\"" + colour +
       "\" stroke-width=\"2\"/>\n";
  s += "  <text x=\"" + number(kLeft + f.plot_w + 40) + "\" y=\"" + number(ly) +
       "\" font-family=\"sans-serif\" font-size=\"11\">" + xml_escape(line.name) + "</text>\n";
  return s;
}

}  // namespace

std::string line_plot_svg(const std::vector<double>& x, const std::vector<LineSeries>& series,
                          const PlotLabels& labels, bool log_y) {
  for (const LineSeries& l : series) {
    CONTACTNN_REQUIRE(l.y.size() == x.size(), "line_plot_svg: series '" << l.name << "' has " << l.y.size()
                                                                        << " values for " << x.size()
                                                                        << " x values");
  }
  const LineFrame frame = line_frame(x, series, log_y);
  std::string s = svg_opening(labels.title) + line_plot_axes(frame, labels, log_y);
  for (std::size_t k = 0; k < series.size(); ++k) s += line_plot_series(frame, x, series[k], k, log_y);
  return s + "</svg>\n";
}

}  // namespace contactnn::eval
