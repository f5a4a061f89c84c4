#include "eval/frontier_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "eval/svg_plot.hpp"

namespace contactnn::eval {

namespace {

std::string f1(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.1f", x);
  return buffer;
}

std::string str(int x) { return std::to_string(x); }

/// A point's family, which colours it.
struct Family {
  const char* name;
  const char* colour;
};
constexpr std::array<Family, 4> kFamilies = {Family{"network", "#1f77b4"}, Family{"hybrid", "#9467bd"},
                                             Family{"closed form", "#2ca02c"}, Family{"newton", "#d62728"}};

std::size_t family(const std::string& method) {
  const auto starts = [&](const char* prefix) { return method.rfind(prefix, 0) == 0; };
  if (method == "four_triangles") return 2;  // closed form too: no iteration (on its own surface)
  if (starts("network+") || starts("closed_form+")) return 1;
  if (starts("network")) return 0;
  if (starts("closed_form")) return 2;
  return 3;
}

/// log10 range of the values with a tenth of a decade to spare, so that no point sits on the frame; at least
/// one decade wide.
std::array<double, 2> log_range(const std::vector<double>& values) {
  double lo = std::log10(*std::min_element(values.begin(), values.end())) - 0.1;
  double hi = std::log10(*std::max_element(values.begin(), values.end())) + 0.1;
  if (hi - lo < 1.0) {
    const double mid = (lo + hi) / 2;
    lo = mid - 0.5;
    hi = mid + 0.5;
  }
  return {lo, hi};
}

struct Box {
  double x0, y0, x1, y1;
  [[nodiscard]] bool overlaps(const Box& b) const { return x0 < b.x1 && b.x0 < x1 && y0 < b.y1 && b.y0 < y1; }
};

/// One panel at (x0, y0), w x h: its frame, axes and points; the labels placed as frontier_svg says.
class Panel {
 public:
  Panel(int x0, int y0, int w, int h, std::array<double, 2> xr, std::array<double, 2> yr)
      : x0_(x0), y0_(y0), h_(h), pw_(w - kMl - kMr), ph_(h - kMt - kMb), xr_(xr), yr_(yr) {}

  void draw(const FrontierPanel& panel, std::vector<std::string>& out) const {
    axes(panel.title, out);
    const std::vector<std::size_t> front = pareto_front(panel.points);
    std::vector<std::array<double, 2>> pts;
    for (std::size_t i = 0; i + 1 < front.size(); ++i) {
      const FrontierPoint &a = panel.points[front[i]], &b = panel.points[front[i + 1]];
      pts.push_back({px(a.ns), py(a.error)});
      pts.push_back({px(b.ns), py(a.error)});
    }
    if (!front.empty()) {
      const FrontierPoint& last = panel.points[front.back()];
      pts.push_back({px(last.ns), py(last.error)});
      pts.push_back({static_cast<double>(x0_ + kMl + pw_), py(last.error)});
    }
    if (!pts.empty()) {
      std::string line =
          "<polyline fill=\"none\" stroke=\"#888\" stroke-width=\"1.5\" stroke-dasharray=\"5,3\" points=\"";
      for (std::size_t i = 0; i < pts.size(); ++i)
        line += (i > 0 ? " " : "") + f1(pts[i][0]) + "," + f1(pts[i][1]);
      out.push_back(line + "\"/>");
    }
    std::vector<Box> boxes;
    for (const FrontierPoint& p : panel.points) {
      const double x = px(p.ns), y = py(p.error);
      boxes.push_back({x - 4, y - 4, x + 4, y + 4});
    }
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      const auto &a = pts[i], &b = pts[i + 1];
      boxes.push_back({std::min(a[0], b[0]) - 1, std::min(a[1], b[1]) - 1, std::max(a[0], b[0]) + 1,
                       std::max(a[1], b[1]) + 1});
    }
    std::vector<bool> on_front(panel.points.size(), false);
    for (const std::size_t i : front) on_front[i] = true;
    std::vector<std::size_t> order(panel.points.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      if (on_front[a] != on_front[b]) return static_cast<bool>(on_front[a]);
      return panel.points[a].ns < panel.points[b].ns;
    });
    for (const std::size_t i : order) point(panel.points[i], on_front[i], boxes, out);
  }

 private:
  static constexpr int kMl = 64, kMr = 16, kMt = 30, kMb = 46;

  [[nodiscard]] double px(double t) const {
    return x0_ + kMl + (std::log10(t) - xr_[0]) / (xr_[1] - xr_[0]) * pw_;
  }
  [[nodiscard]] double py(double e) const {
    return y0_ + kMt + (yr_[1] - std::log10(std::max(e, kZeroErrorFloor))) / (yr_[1] - yr_[0]) * ph_;
  }

  /// The title, the frame, the grid lines at the decades (x: also at 2..9 times them) and their labels, the
  /// axis labels.
  void axes(const std::string& title, std::vector<std::string>& out) const {
    out.push_back("<text x=\"" + f1(x0_ + kMl + pw_ / 2.0) + "\" y=\"" + str(y0_ + 18) +
                  "\" text-anchor=\"middle\" font-size=\"13\">" + xml_escape(title) + "</text>");
    out.push_back("<rect x=\"" + str(x0_ + kMl) + "\" y=\"" + str(y0_ + kMt) + "\" width=\"" + str(pw_) +
                  "\" height=\"" + str(ph_) + "\" fill=\"none\" stroke=\"#000\"/>");
    for (int d = static_cast<int>(std::floor(xr_[0])); d <= static_cast<int>(std::ceil(xr_[1])); ++d) {
      for (int k = 1; k < 10; ++k) {
        const double v = std::log10(static_cast<double>(k)) + d;
        if (!(xr_[0] <= v && v <= xr_[1])) continue;
        const double x = px(std::pow(10.0, v));
        out.push_back("<line x1=\"" + f1(x) + "\" y1=\"" + str(y0_ + kMt) + "\" x2=\"" + f1(x) + "\" y2=\"" +
                      str(y0_ + kMt + ph_) + "\" stroke=\"" + (k == 1 ? "#ccc" : "#eee") + "\"/>");
        if (k == 1 || ((k == 2 || k == 5) && xr_[1] - xr_[0] <= 2)) {
          char tick[32];
          std::snprintf(tick, sizeof tick, "%g", k * std::pow(10.0, d));
          out.push_back("<text x=\"" + f1(x) + "\" y=\"" + str(y0_ + kMt + ph_ + 16) +
                        "\" text-anchor=\"middle\" font-size=\"11\">" + tick + "</text>");
        }
      }
    }
    const int step = yr_[1] - yr_[0] <= 10 ? 1 : 2;
    for (int d = static_cast<int>(std::ceil(yr_[0])); d <= static_cast<int>(std::floor(yr_[1])); ++d) {
      const double y = py(std::pow(10.0, d));
      out.push_back("<line x1=\"" + str(x0_ + kMl) + "\" y1=\"" + f1(y) + "\" x2=\"" + str(x0_ + kMl + pw_) +
                    "\" y2=\"" + f1(y) + "\" stroke=\"#ccc\"/>");
      if (d % step == 0) {
        out.push_back("<text x=\"" + str(x0_ + kMl - 6) + "\" y=\"" + f1(y + 4) +
                      "\" text-anchor=\"end\" font-size=\"11\">1e" + str(d) + "</text>");
      }
    }
    out.push_back(
        "<text x=\"" + f1(x0_ + kMl + pw_ / 2.0) + "\" y=\"" + str(y0_ + h_ - 8) +
        "\" text-anchor=\"middle\" font-size=\"12\">ns per query, batched, 1 thread (median)</text>");
    out.push_back(
        "<text transform=\"translate(" + str(x0_ + 16) + "," + f1(y0_ + kMt + ph_ / 2.0) +
        ") rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">effective mean |error| (failures count "
        "as one domain width)</text>");
  }

  /// Where a label goes: its anchor point, alignment, box, and its distance from the point.
  struct Placement {
    double x, y;
    const char* anchor;
    Box box;
    int dist;
  };

  /// The first candidate place round (x, y) inside the frame that overlaps no box; beside the point on the
  /// side with room when none is free.
  [[nodiscard]] Placement place(double x, double y, double tw, const std::vector<Box>& boxes) const {
    constexpr double th = 10.0;
    for (const int dist : {6, 14, 26, 40}) {
      const std::array<std::pair<std::array<int, 2>, const char*>, 8> candidates = {{
          {{dist, 3}, "start"},
          {{-dist, 3}, "end"},
          {{dist, -dist}, "start"},
          {{dist, dist + 6}, "start"},
          {{-dist, -dist}, "end"},
          {{-dist, dist + 6}, "end"},
          {{0, -dist}, "middle"},
          {{0, dist + 9}, "middle"},
      }};
      for (const auto& [offset, anchor] : candidates) {
        const double lx = x + offset[0];
        const std::string_view a = anchor;
        const double left = a == "start" ? lx : a == "end" ? lx - tw : lx - tw / 2;
        const Box box{left, y + offset[1] - th + 1, left + tw, y + offset[1] + 2};
        const bool inside = box.x0 >= x0_ + kMl && box.x1 <= x0_ + kMl + pw_ && box.y0 >= y0_ + kMt &&
                            box.y1 <= y0_ + kMt + ph_;
        if (inside &&
            std::none_of(boxes.begin(), boxes.end(), [&](const Box& b) { return box.overlaps(b); })) {
          return {lx, y + offset[1], anchor, box, dist};
        }
      }
    }
    if (x + 6 + tw <= x0_ + kMl + pw_) return {x + 6, y + 3, "start", {x + 6, y - 7, x + 6 + tw, y + 5}, 6};
    return {x - 6, y + 3, "end", {x - 6 - tw, y - 7, x - 6, y + 5}, 6};
  }

  /// A point, its label (newton:K as K) and, for a label placed far, a line to it.
  void point(const FrontierPoint& p, bool on_front, std::vector<Box>& boxes,
             std::vector<std::string>& out) const {
    const double x = px(p.ns), y = py(p.error);
    const std::string colour = kFamilies[family(p.method)].colour;
    out.push_back("<circle cx=\"" + f1(x) + "\" cy=\"" + f1(y) + "\" r=\"" + (on_front ? "4.5" : "3.2") +
                  "\" fill=\"" + colour + "\"" + (on_front ? " stroke=\"#000\" stroke-width=\"1\"" : "") +
                  "/>");
    const std::string label = p.method.rfind("newton:", 0) == 0 ? p.method.substr(7) : p.method;
    const Placement at = place(x, y, 5.6 * static_cast<double>(label.size()), boxes);
    boxes.push_back(at.box);
    if (at.dist > 14) {
      out.push_back("<line x1=\"" + f1(x) + "\" y1=\"" + f1(y) + "\" x2=\"" +
                    f1((at.box.x0 + at.box.x1) / 2) + "\" y2=\"" + f1((at.box.y0 + at.box.y1) / 2) +
                    "\" stroke=\"" + colour + "\" stroke-width=\"0.5\"/>");
    }
    out.push_back("<text x=\"" + f1(at.x) + "\" y=\"" + f1(at.y) + "\" text-anchor=\"" + at.anchor +
                  "\" font-size=\"10\" fill=\"" + colour + "\">" + xml_escape(label) + "</text>");
  }

  int x0_, y0_, h_, pw_, ph_;
  std::array<double, 2> xr_, yr_;
};

}  // namespace

std::string frontier_svg(const std::vector<FrontierPanel>& panels) {
  std::vector<double> xs, ys;
  std::array<bool, kFamilies.size()> present{};
  bool zero = false;
  for (const FrontierPanel& panel : panels) {
    for (const FrontierPoint& p : panel.points) {
      xs.push_back(p.ns);
      ys.push_back(std::max(p.error, kZeroErrorFloor));
      present[family(p.method)] = true;
      zero = zero || p.error == 0;
    }
  }
  const std::array<double, 2> xr = xs.empty() ? std::array<double, 2>{0, 1} : log_range(xs);
  const std::array<double, 2> yr = ys.empty() ? std::array<double, 2>{0, 1} : log_range(ys);
  constexpr int pw = 640, ph = 560;
  const int w = pw * static_cast<int>(panels.size()), h = ph + 40;
  std::vector<std::string> body = {
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + str(w) + "\" height=\"" + str(h) +
          "\" viewBox=\"0 0 " + str(w) + " " + str(h) + "\" font-family=\"sans-serif\">",
      "<rect width=\"" + str(w) + "\" height=\"" + str(h) + "\" fill=\"#fff\"/>"};
  for (std::size_t i = 0; i < panels.size(); ++i) {
    Panel(static_cast<int>(i) * pw, 0, pw, ph, xr, yr).draw(panels[i], body);
  }
  int lx = 70;
  for (std::size_t f = 0; f < kFamilies.size(); ++f) {
    if (!present[f]) continue;
    const std::string text = f == 3 ? "newton (K: newton:K, K fixed steps)" : kFamilies[f].name;
    body.push_back("<circle cx=\"" + str(lx) + "\" cy=\"" + str(ph + 18) + "\" r=\"4\" fill=\"" +
                   kFamilies[f].colour + "\"/><text x=\"" + str(lx + 8) + "\" y=\"" + str(ph + 22) +
                   "\" font-size=\"12\">" + text + "</text>");
    lx += 30 + 7 * static_cast<int>(text.size());
  }
  body.push_back("<text x=\"" + str(lx) + "\" y=\"" + str(ph + 22) +
                 "\" font-size=\"12\">dashed: Pareto front (outlined points)" +
                 (zero ? "; an error of 0 is drawn at 1e-17" : "") + "</text>");
  body.push_back("</svg>");
  std::string out;
  for (const std::string& line : body) out += line + "\n";
  return out;
}

}  // namespace contactnn::eval
