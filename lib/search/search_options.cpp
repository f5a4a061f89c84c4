#include "search/search_options.hpp"

#include <cmath>

#include "core/error.hpp"

namespace contactnn::search {

namespace {

/// InvalidArgument "NAME = VALUE, expected LO to HI" unless lo <= value <= hi (lo < value when lo_open) and
/// finite.
void require_in(const char* name, double value, double lo, double hi, bool lo_open = false) {
  const bool above_lo = lo_open ? value > lo : value >= lo;
  CONTACTNN_REQUIRE_AS(InvalidArgument, std::isfinite(value) && above_lo && value <= hi,
                       name << " = " << value << ", expected a finite number " << (lo_open ? "> " : "from ")
                            << lo << (lo_open ? " and <= " : " to ") << hi);
}

}  // namespace

void check_search_options(const SearchOptions& options) {
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       options.max_iterations >= 1 && options.max_iterations <= kMaxIterations,
                       "max_iterations = " << options.max_iterations << ", expected 1 to " << kMaxIterations);
  CONTACTNN_REQUIRE_AS(InvalidArgument, options.max_halvings >= 0 && options.max_halvings <= kMaxHalvings,
                       "max_halvings = " << options.max_halvings << ", expected 0 to " << kMaxHalvings);
  require_in("tol_param", options.tol_param, 0.0, kMaxTolParam);
  require_in("domain_margin", options.domain_margin, 0.0, kMaxDomainMargin);
  require_in("gregory_box_margin", options.gregory_box_margin, 0.0, kMaxBoxMargin);
  require_in("bilinear_box_margin", options.bilinear_box_margin, 0.0, kMaxBoxMargin);
  require_in("max_step_widths", options.max_step_widths, 0.0, kMaxStepWidths, true);
}

}  // namespace contactnn::search
