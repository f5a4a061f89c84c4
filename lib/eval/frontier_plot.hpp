// The speed-accuracy frontier as a stand-alone SVG file (scripts/frontier's plot, written by evaluate-net
// --frontier): one panel per evaluation set, every method a point, the Pareto front drawn.
#pragma once

#include <string>
#include <vector>

#include "eval/ranking.hpp"

namespace contactnn::eval {

/// One panel: its title and its points (frontier_points of a set).
struct FrontierPanel {
  std::string title;
  std::vector<FrontierPoint> points;
};

/// Where an error of exactly 0 is drawn on the log axis.
inline constexpr double kZeroErrorFloor = 1e-17;

/// SVG document, 640 x 600 user units a panel, side by side: effective mean |error| (log) against batched
/// 1-thread ns/query (log), both axes' ranges shared by every panel (a tenth of a decade to spare, at least a
/// decade wide); grid lines at the decades; the Pareto front (pareto_front) as a dashed staircase, its points
/// outlined; each point coloured by its method's family (network, hybrid, closed form, newton) and labelled
/// (newton:K as K), each label at the first of a few places round its point that overlaps no point, no part
/// of the front and no earlier label; a legend of the families present.
[[nodiscard]] std::string frontier_svg(const std::vector<FrontierPanel>& panels);

}  // namespace contactnn::eval
