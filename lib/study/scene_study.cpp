#include "study/scene_study.hpp"

#include <algorithm>
#include <cmath>

#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/input_features.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "study/study_detail.hpp"

namespace contactnn::study {

using detail::join;
using detail::split_methods;

namespace {
constexpr std::array<std::string_view, 3> kTrainNetworksNames = {"auto", "always", "never"};
constexpr std::array<std::string_view, 3> kDomainStatesNames = {"auto", "rest", "history"};
}  // namespace

std::string_view to_string(TrainNetworks mode) { return enum_name(kTrainNetworksNames, mode, "unknown"); }

std::string_view to_string(DomainStates states) { return enum_name(kDomainStatesNames, states, "unknown"); }

DomainStates domain_states_from_string(std::string_view name) {
  if (const auto states = enum_from_name<DomainStates>(kDomainStatesNames, name)) return *states;
  throw InvalidArgument("domain: expected auto, rest or history, got '" + std::string(name) + "'");
}

TrainNetworks train_networks_from_string(std::string_view name) {
  if (const auto mode = enum_from_name<TrainNetworks>(kTrainNetworksNames, name)) return *mode;
  throw InvalidArgument("train_networks: expected auto, always or never, got '" + std::string(name) + "'");
}

std::string default_methods(SurfaceKind surface) {
  std::string list =
      "closed_form,closed_form+newton:1,closed_form+newton:2,closed_form+newton:3,newton:1,newton:2,"
      "newton:3,newton:4,newton:5,newton";
  if (surface == SurfaceKind::kBilinear) {
    // The methods of lib/search that other work adds, where this build has them.
    for (const char* extra : {"four_triangles"}) {
      try {
        (void)search::Method::parse(extra);
        list += std::string(",") + extra;
      } catch (const InvalidArgument&) {
      }
    }
  }
  return list;
}

SceneStudyOptions resolved(SceneStudyOptions o, SurfaceKind surface) {
  const bool gregory = surface == SurfaceKind::kGregory;
  if (o.sizes.empty()) o.sizes = gregory ? std::vector<int>{16, 32, 48} : std::vector<int>{8, 16, 32};
  if (!(o.target > 0.0)) o.target = gregory ? 0.0025 : 0.005;
  if (!(o.learning_rate > 0.0)) o.learning_rate = gregory ? 0.01 : 0.02;
  if (o.methods.empty()) o.methods = default_methods(surface);
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.count >= 100, "count = " << o.count << ", expected at least 100");
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.heldout_divisor >= 1,
                       "heldout_divisor = " << o.heldout_divisor << ", expected >= 1");
  for (const int h : o.sizes) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, h >= 1 && h <= search::NetworkModel::kMaxWidth,
                         "sizes: " << h << " hidden units, expected 1.." << search::NetworkModel::kMaxWidth);
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, std::is_sorted(o.sizes.begin(), o.sizes.end()),
                       "sizes " << join(o.sizes) << ": expected the smallest first");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, o.epochs >= 1 && o.long_epochs >= 0,
      "epochs " << o.epochs << " and long_epochs " << o.long_epochs << ": expected >= 1 and >= 0");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, std::isfinite(o.target) && std::isfinite(o.margin) && o.margin > 0.0,
      "target " << o.target << " and margin " << o.margin << ": expected finite numbers > 0");
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       o.train_fraction > 0.0 && o.train_fraction <= 1.0 && o.validation_fraction >= 0.0,
                       "train_fraction " << o.train_fraction << " must be in (0, 1], validation_fraction "
                                         << o.validation_fraction << " >= 0");
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.timing_queries >= 1, "timing_queries = " << o.timing_queries);
  (void)input_features_from_string(o.input_features);
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.capture_pairs == "nearest_node" || o.capture_pairs == "surface",
                       "capture_pairs: expected nearest_node or surface, got '" << o.capture_pairs << "'");
  for (const std::string& m : split_methods(o.methods)) {
    const search::Method method = search::Method::parse(m);
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_network() && !method.needs_start(),
                         "methods: '"
                             << m
                             << "' needs a network or a caller's start; scene networks' methods go in "
                                "network_methods");
    (void)search::LocalSearch(surface, method);  // a method the surface has (four_triangles: bilinear only)
  }
  for (const std::string& m : split_methods(o.network_methods)) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, search::Method::parse(m).needs_network(),
                         "network_methods: '" << m << "' uses no network; it belongs in methods");
  }
  return o;
}

}  // namespace contactnn::study
