// A histogram as a stand-alone SVG file, written by hand (no plotting dependency).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "eval/histogram.hpp"

namespace contactnn::eval {

/// Text of a histogram plot.
struct PlotLabels {
  std::string title;    ///< e.g. "Network 8-8-2: error in xi (network - Newton), 717784 configurations"
  std::string x_label;  ///< e.g. "error in xi"
  std::string y_label = "frequency";
};

/// SVG 1.1 document (UTF-8, one root <svg> element, 760 x 460 user units): one bar per bin, x axis with
/// ticks at "nice" values and their labels, y axis (counts, linear from 0) with ticks and labels, axis
/// labels, the title, and a footnote with the underflow, overflow and excluded counts (values outside the
/// plotted range are counted there, never dropped). Text is XML-escaped.
[[nodiscard]] std::string histogram_svg(const Histogram& histogram, const PlotLabels& labels);

/// One named line of a line plot: y[i] at the plot's x[i].
struct LineSeries {
  std::string name;
  std::vector<double> y;
};

/// SVG 1.1 document (760 x 460 user units) of lines over a common x (e.g. a history's increments): one
/// polyline and legend entry per series, axes with nice ticks, axis labels and the title. With `log_y` the
/// y axis is log10 (decades as ticks) and values <= 0 or not finite leave a gap in their line; otherwise
/// such non-finite values leave a gap. InvalidArgument if a series' length differs from x's.
[[nodiscard]] std::string line_plot_svg(const std::vector<double>& x, const std::vector<LineSeries>& series,
                                        const PlotLabels& labels, bool log_y);

/// `text` with &, <, >, " and ' replaced by their XML entities.
[[nodiscard]] std::string xml_escape(std::string_view text);

/// Tick values for an axis over [lo, hi]: multiples of a nice step (1, 2 or 5 times a power of ten)
/// chosen so that there are about `target` ticks (at least 2 for lo < hi); all inside [lo, hi] up to
/// rounding of the step.
[[nodiscard]] std::vector<double> nice_ticks(double lo, double hi, int target);

/// A tick label: shortest of %g with 1..6 significant digits that reads back within 1e-9 of the step
/// (so 0.1 is "0.1", 2e-05 is "2e-05").
[[nodiscard]] std::string tick_label(double value, double step);

}  // namespace contactnn::eval
