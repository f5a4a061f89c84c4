// Tests of lib/eval/svg_plot: well-formed XML, axes, ticks, labels, escaping; and of the test's own XML
// check.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "eval/svg_plot.hpp"
#include "xml_check.hpp"

namespace contactnn::eval {
namespace {

using contactnn::testing::xml_well_formedness_error;

Histogram sample_histogram() {
  std::vector<double> v;
  for (int i = 0; i < 1000; ++i) v.push_back(0.004 * std::sin(0.37 * i) * std::cos(0.11 * i));
  v.push_back(0.5);   // overflow
  v.push_back(-0.5);  // underflow
  std::vector<std::uint8_t> failed(v.size(), 0);
  failed[3] = 1;
  return make_histogram(v, failed, -0.005, 0.005, 50);
}

TEST(XmlCheck, AcceptsWellFormedAndRejectsMalformed) {
  EXPECT_EQ(xml_well_formedness_error("<?xml version=\"1.0\"?>\n<a x=\"1\"><b/>t &amp; &#60;</a>\n"), "");
  EXPECT_NE(xml_well_formedness_error("<a><b></a></b>"), "");        // bad nesting
  EXPECT_NE(xml_well_formedness_error("<a x=1/>"), "");              // unquoted attribute
  EXPECT_NE(xml_well_formedness_error("<a>x & y</a>"), "");          // raw ampersand
  EXPECT_NE(xml_well_formedness_error("<a>1 < 2</a>"), "");          // raw '<'
  EXPECT_NE(xml_well_formedness_error("<a/><b/>"), "");              // two roots
  EXPECT_NE(xml_well_formedness_error("<a x=\"1\" x=\"2\"/>"), "");  // duplicate attribute
  EXPECT_NE(xml_well_formedness_error("<a>"), "");                   // unclosed
}

TEST(HistogramSvg, IsWellFormedXml) {
  PlotLabels labels;
  labels.title = "Network 8-8-2: error in xi <network - Newton> & \"quotes\"";
  labels.x_label = "error in xi";
  const std::string svg = histogram_svg(sample_histogram(), labels);
  EXPECT_EQ(xml_well_formedness_error(svg), "") << svg.substr(0, 400);
  EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
}

TEST(HistogramSvg, HasTitleAxisLabelsTicksAndOutlierNote) {
  PlotLabels labels;
  labels.title = "Network 8-8-2: error in eta";
  labels.x_label = "error in eta";
  const Histogram h = sample_histogram();
  const std::string svg = histogram_svg(h, labels);
  EXPECT_NE(svg.find(">Network 8-8-2: error in eta</text>"), std::string::npos);
  EXPECT_NE(svg.find(">error in eta</text>"), std::string::npos);
  EXPECT_NE(svg.find(">frequency</text>"), std::string::npos);
  // x ticks over [-0.005, 0.005] in steps of 0.002 (nice_ceil(0.01 / 8) = 0.002) and the zero tick.
  EXPECT_NE(svg.find(">-0.004</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0.004</text>"), std::string::npos);
  EXPECT_NE(svg.find("1 below, 1 above; 1 failures not plotted"), std::string::npos);
  // One bar per non-empty bin (plus the white background rect).
  std::size_t rects = 0;
  for (std::size_t p = svg.find("<rect"); p != std::string::npos; p = svg.find("<rect", p + 1)) ++rects;
  std::size_t non_empty = 0;
  for (const auto c : h.counts) non_empty += c > 0 ? 1 : 0;
  EXPECT_EQ(rects, non_empty + 1);
}

TEST(HistogramSvg, EscapesText) {
  EXPECT_EQ(xml_escape("a<b & \"c\" 'd'>"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
}

TEST(NiceTicks, CoverTheRangeWithNiceSteps) {
  EXPECT_EQ(nice_ticks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0}));
  const std::vector<double> t = nice_ticks(-0.03, 0.03, 6);
  ASSERT_FALSE(t.empty());
  EXPECT_NEAR(t.front(), -0.03, 1e-15);
  EXPECT_NEAR(t.back(), 0.03, 1e-15);
  EXPECT_EQ(tick_label(0.6000000000000001, 0.2), "0.6");
  EXPECT_EQ(tick_label(2e-5, 1e-5), "2e-05");
  EXPECT_EQ(tick_label(250000.0, 50000.0), "2.5e+05");
}

}  // namespace
}  // namespace contactnn::eval
