#include "history/plan_search.hpp"

#include "core/error.hpp"
#include "io/network_model_file.hpp"

namespace contactnn::history {

PlanSearch load_plan_search(const std::filesystem::path& plan_file) {
  PlanSearch s;
  s.plan = io::read_plan(plan_file);
  const std::filesystem::path network_file = io::plan_network_path(s.plan, plan_file);
  if (!network_file.empty()) {
    s.network = io::read_network_model(network_file);
    CONTACTNN_REQUIRE_AS(FormatError, s.network->surface() == s.plan.surface,
                         "'" << network_file.string() << "' is a " << to_string(s.network->surface())
                             << " network, the plan '" << plan_file.string() << "' is for "
                             << to_string(s.plan.surface) << " surfaces");
  }
  s.locator = std::make_unique<contact::FaceLocator>(s.plan.method, s.network.get());
  s.label = plan_file.string() + ": " + s.plan.method;
  return s;
}

PlanSearch method_search(const std::string& method, SurfaceKind surface,
                         const std::filesystem::path& network_file) {
  PlanSearch s;
  s.plan.method = method;
  s.plan.surface = surface;
  if (!network_file.empty()) s.network = io::read_network_model(network_file);
  s.locator = std::make_unique<contact::FaceLocator>(method, s.network.get());
  s.label = method;
  return s;
}

}  // namespace contactnn::history
