// Steps 3 and 5 of the scene study (scene_study.hpp): every candidate method measured on the held-out sample
// (accuracy, and batched 1-thread speed in one round-robin), the sizes worth training, and the plan's choice:
// the fastest method that reaches margin x target, else the most accurate.
#pragma once

#include <string>
#include <vector>

#include "eval/accuracy.hpp"
#include "eval/evaluation_set.hpp"
#include "search/local_search.hpp"
#include "study/scene_networks.hpp"
#include "study/scene_study.hpp"

namespace contactnn::study {

/// One method on the held-out sample.
struct MethodMeasurement {
  std::string name;    ///< e.g. "closed_form", "network+newton:1[16-32-2]"
  std::string method;  ///< the search::Method name
  int network = -1;    ///< index into the networks measured, -1: none
  eval::MethodErrors errors;
  double effective_mean = 0.0;  ///< eval::effective_mean_error
  double batched_ns = 0.0;      ///< ns per query, batched, 1 thread: the fastest of the timed passes
  bool reaches = false;         ///< effective_mean <= margin x target
};

/// Every method of `methods` (comma-separated, no network) and `network_methods` with each of `networks` on
/// `set`: accuracy (options.threads) and batched 1-thread speed, all timed in one round-robin; each method's
/// time is its fastest pass (another process can only slow a pass down).
[[nodiscard]] std::vector<MethodMeasurement> measure_methods(const eval::EvaluationSet& set,
                                                             SurfaceKind surface, const std::string& methods,
                                                             const std::string& network_methods,
                                                             const std::vector<const SceneNetwork*>& networks,
                                                             const SceneStudyOptions& options);

/// The sizes worth training (step 3): with kAlways all, kNever none; with kAuto each size whose untrained
/// network alone (in `measured`, named "network[<name>]") is faster than the fastest method of `measured`
/// that reaches the target (every size when none does). `why` gets one line per size left out.
[[nodiscard]] std::vector<int> sizes_that_may_pay(const std::vector<MethodMeasurement>& measured,
                                                  const std::vector<SceneNetwork>& untrained,
                                                  const SceneStudyOptions& options,
                                                  std::vector<std::string>* why);

/// A method displaces an earlier one that also reaches the target only where its time is below this fraction
/// of the earlier one's: closer times are the machine's noise (a study of 4 pairs under ctest -j2 chose
/// newton:4 over newton:2 once in 30 runs), and the same study should give the same plan.
inline constexpr double kPlanNoise = 0.9;

/// The plan's method (step 5): the index in `measured` of the fastest that reaches the target (in the order
/// measured, a later one only where kPlanNoise faster), else of the most accurate (ties: the faster).
/// InvalidArgument for an empty list.
[[nodiscard]] std::size_t choose_plan(const std::vector<MethodMeasurement>& measured);

/// The search of measurement `m` (its method, with its network of `networks` where it has one).
[[nodiscard]] search::LocalSearch method_search(SurfaceKind surface, const MethodMeasurement& m,
                                                const std::vector<const SceneNetwork*>& networks);

}  // namespace contactnn::study
