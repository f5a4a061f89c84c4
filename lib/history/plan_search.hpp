// The plan in the loop (issue 38): a scene plan (io/plan_file.hpp) or a method name made into the surface
// search's face locator (contact/narrow_phase.hpp), with the network it needs, for replay --plan and
// gen-configs --scene --plan.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "contact/narrow_phase.hpp"
#include "io/plan_file.hpp"
#include "search/network_model.hpp"

namespace contactnn::history {

/// A locator and what it needs, owned together (the network must outlive the locator).
struct PlanSearch {
  io::ScenePlan plan;  ///< read from the file; for a method name, its method and surface only
  std::unique_ptr<search::NetworkModel> network;
  std::unique_ptr<contact::FaceLocator> locator;
  std::string label;  ///< how reports name it: "PLAN: METHOD" or the method
};

/// The plan in `plan_file`: its method, its network (relative to the plan's directory) in the precision it
/// was trained in, its surface and target. IoError / FormatError from read_plan and the network's reader;
/// FormatError for a network of another surface than the plan's; InvalidArgument for a method the surface
/// search cannot run (FaceLocator).
[[nodiscard]] PlanSearch load_plan_search(const std::filesystem::path& plan_file);

/// `method` (a search::Method name) on `surface`, with the network in `network_file` (empty: none) for a
/// network method; target 0 (none).
[[nodiscard]] PlanSearch method_search(const std::string& method, SurfaceKind surface,
                                       const std::filesystem::path& network_file);

}  // namespace contactnn::history
