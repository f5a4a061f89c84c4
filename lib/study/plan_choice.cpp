// The plan's choice (step 5, method_measurement.hpp: choose_plan) and the plan file's content
// (scene_report.hpp: make_plan).
#include <algorithm>

#include "core/error.hpp"
#include "study/method_measurement.hpp"
#include "study/scene_report.hpp"

namespace contactnn::study {

std::size_t choose_plan(const std::vector<MethodMeasurement>& measured) {
  CONTACTNN_REQUIRE(!measured.empty(), "no method measured: nothing to choose from");
  std::size_t best = 0;
  bool any = false;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    if (!measured[i].reaches) continue;
    if (!any || measured[i].batched_ns < kPlanNoise * measured[best].batched_ns) best = i;
    any = true;
  }
  if (any) return best;
  for (std::size_t i = 1; i < measured.size(); ++i) {
    const MethodMeasurement &a = measured[i], &b = measured[best];
    if (a.effective_mean < b.effective_mean ||
        (a.effective_mean == b.effective_mean && a.batched_ns < b.batched_ns))
      best = i;
  }
  return best;
}

io::ScenePlan make_plan(const SceneStudyResult& r, const std::string& network_file) {
  io::ScenePlan plan;
  plan.surface = r.surface;
  plan.method = r.plan().method;
  plan.network = network_file;
  plan.target = r.options.target;
  plan.margin = r.options.margin;
  plan.reached = r.plan().reaches;
  plan.domain.deck = r.deck;
  plan.domain.pair = r.pair;
  plan.domain.deformation = r.domain.deformation;
  plan.domain.capture = r.domain.capture;
  plan.domain.normal_tilt_tangent = r.domain.normal_tilt_tangent;
  plan.domain.boundary_fraction = r.domain.boundary_fraction;
  plan.domain.heldout_count = r.heldout_rows;
  plan.domain.heldout_seed = static_cast<std::int64_t>(r.heldout_seed);
  plan.domain.segment_test = r.domain.segment_test;
  plan.domain.states = r.options.domain_states == DomainStates::kHistory ? "history" : "rest";
  plan.domain.results = r.results;
  for (const MethodMeasurement& m : r.measured) {
    io::PlanMeasurement p;
    p.method = m.name;
    p.mean_abs[0] = m.errors.stats[0].mean_abs;
    p.mean_abs[1] = m.errors.stats[1].mean_abs;
    p.effective_mean = m.effective_mean;
    p.max_abs = std::max(m.errors.stats[0].max_abs, m.errors.stats[1].max_abs);
    p.failures = m.errors.failures_method;
    p.batched_ns = m.batched_ns;
    p.reaches_target = m.reaches;
    plan.measurements.push_back(std::move(p));
  }
  return plan;
}

}  // namespace contactnn::study
