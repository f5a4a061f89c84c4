#include "search/method.hpp"

#include <charconv>

#include "core/error.hpp"

namespace contactnn::search {

namespace {

constexpr std::string_view kForms =
    "expected one of: network, newton, newton:K, closed_form, start, network+newton:K, closed_form+newton:K, "
    "start+newton:K, four_triangles "
    "(K an integer from 0 to 1000)";

/// The K of "...newton:K": a decimal integer in [0, Method::kMaxSteps] filling the whole of `text`.
int parse_steps(std::string_view text, std::string_view whole) {
  int k = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), k);
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       error == std::errc() && end == text.data() + text.size() && k >= 0 && !text.empty(),
                       "method '" << whole << "': '" << text << "' is not a step count >= 0; " << kForms);
  CONTACTNN_REQUIRE_AS(InvalidArgument, k <= Method::kMaxSteps,
                       "method '" << whole << "': " << k << " steps, more than the limit of "
                                  << Method::kMaxSteps << " (for Newton until it converges use 'newton'); "
                                  << kForms);
  return k;
}

}  // namespace

Method Method::parse(std::string_view name) {
  if (name == "network") return Method{Start::kNetwork, 0, false};
  if (name == "closed_form") return Method{Start::kClosedForm, 0, false};
  if (name == "newton") return Method{Start::kCentre, 0, true};
  if (name == "start") return Method{Start::kGiven, 0, false};
  if (name == "four_triangles") return Method{Start::kFourTriangles, 0, false};
  constexpr std::string_view kNewton = "newton:";
  constexpr std::string_view kNetworkNewton = "network+newton:";
  constexpr std::string_view kClosedNewton = "closed_form+newton:";
  constexpr std::string_view kStartNewton = "start+newton:";
  if (name.starts_with(kNewton))
    return Method{Start::kCentre, parse_steps(name.substr(kNewton.size()), name), false};
  if (name.starts_with(kNetworkNewton)) {
    return Method{Start::kNetwork, parse_steps(name.substr(kNetworkNewton.size()), name), false};
  }
  if (name.starts_with(kClosedNewton)) {
    return Method{Start::kClosedForm, parse_steps(name.substr(kClosedNewton.size()), name), false};
  }
  if (name.starts_with(kStartNewton)) {
    return Method{Start::kGiven, parse_steps(name.substr(kStartNewton.size()), name), false};
  }
  throw InvalidArgument("unknown local-search method '" + std::string(name) + "'; " + std::string(kForms));
}

std::string Method::name() const {
  const std::string k = std::to_string(newton_steps);
  switch (start) {
    case Start::kCentre: return to_convergence ? "newton" : "newton:" + k;
    case Start::kNetwork: return newton_steps == 0 ? "network" : "network+newton:" + k;
    case Start::kClosedForm: return newton_steps == 0 ? "closed_form" : "closed_form+newton:" + k;
    case Start::kGiven: return newton_steps == 0 ? "start" : "start+newton:" + k;
    // With steps (not a form parse gives; LocalSearch refuses it) the name says what was asked.
    case Start::kFourTriangles: return newton_steps == 0 ? "four_triangles" : "four_triangles+newton:" + k;
  }
  return "unknown";
}

}  // namespace contactnn::search
