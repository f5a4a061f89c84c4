// The scene plan (SPEC 7): the local-search method scene-study chose for one contact pair of a deck, with its
// network file if it needs one, the domain and target it was chosen for, and what the study measured of every
// method it tried. Written by scene-study as DIR/plan.toml; read by evaluate-net --plan, the C interface
// (contactnn_search_create_from_plan) and the Fortran module (contactnn_create_from_plan), which load it in
// place of a method string and a network file.
//
// The file is TOML 1.0 (read and checked with toml++, header-only: the C library carries no run-time
// dependency for it):
//
//   [plan]                                 required
//   schema_version = 1                     integer, kPlanSchemaVersion
//   surface = "gregory"                    "bilinear" or "gregory"
//   method = "network+newton:1"            a search::Method name (search/method.hpp)
//   network = "network.h5"                 the network file, relative to the plan's own directory (or
//                                          absolute); "" for a method without a network. Required exactly
//                                          when the method needs one.
//   target = 0.0025                        mean |error| (parameter units) the method had to reach, > 0
//   margin = 0.8                           the held-out sample had to show margin x target, > 0
//   reached = true                         whether the method reached it (false: no method did; the most
//                                          accurate was kept)
//   [domain]                               required: the scene's domain the methods were measured on
//   deck = "hueeber1.inp"                  the deck, as given to scene-study
//   pair = 0                               integer >= 0
//   deformation = 0.1                      dataset::SceneDomainOptions, the values used (capture: after
//   capture = 0.5                          widening to the deck's own offsets)
//   normal_tilt_tangent = 0.1
//   boundary_fraction = 0.2
//   heldout_count = 15000                  configurations of the held-out sample, integer >= 1
//   heldout_seed = 1001                    its seed, integer >= 0
//   segment_test = true                    optional (default true): whether the domain's slave nodes pass the
//                                          segment test of Eqs 3-6
//                                          (dataset::SceneDomainOptions::segment_test)
//   states = "history"                     optional (default "rest"): the states the domain was drawn from,
//   the
//                                          deck ("rest") or the deck and every increment of `results`
//   results = "run.frd"                    optional (default ""): the solver's results the study was given
//                                          (scene-study --results), as given
//   [[measurement]]                        optional, any number: one per method measured
//   method = "closed_form"                 the study's name of the method ("network[16-32-2]" for a network)
//   mean_abs = [1.2e-3, 3.4e-3]            held-out mean |error| of each coordinate (failures left out)
//   effective_mean = 3.4e-3                the larger coordinate's mean |error| with each failure counted as
//                                          one domain width (eval::effective_mean_error): what is compared
//                                          with margin x target
//   max_abs = 0.05                         largest |error| of either coordinate
//   failures = 0                           integer >= 0
//   batched_ns = 103.2                     time per query, batched, 1 thread, on the held-out sample (the
//                                          fastest of the timed passes)
//   reaches_target = true
//
// Reading is strict, as the tools' config files: a TOML syntax error, an unknown table or key, a missing
// required key, a value of the wrong type or out of range is a FormatError naming the file, the line and the
// key. An integer is accepted where a real is expected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/conventions.hpp"

namespace contactnn::io {

inline constexpr std::int64_t kPlanSchemaVersion = 1;

/// One method the study measured on the held-out sample of the scene's domain.
struct PlanMeasurement {
  std::string method;               ///< e.g. "closed_form+newton:1", "network[16-32-2]"
  double mean_abs[2] = {0.0, 0.0};  ///< per coordinate, parameter units
  double effective_mean = 0.0;      ///< eval::effective_mean_error
  double max_abs = 0.0;
  std::int64_t failures = 0;
  double batched_ns = 0.0;  ///< ns per query, batched, 1 thread
  bool reaches_target = false;
};

/// The domain the plan was chosen on (dataset::SceneDomainOptions and the held-out sample).
struct PlanDomain {
  std::string deck;
  std::int64_t pair = 0;
  double deformation = 0.0;
  double capture = 0.0;
  double normal_tilt_tangent = 0.0;
  double boundary_fraction = 0.0;
  std::int64_t heldout_count = 0;
  std::int64_t heldout_seed = 0;
  bool segment_test = true;
  std::string states = "rest";  ///< "rest" or "history"
  std::string results;          ///< scene-study --results, or empty
};

struct ScenePlan {
  SurfaceKind surface = SurfaceKind::kBilinear;
  std::string method;   ///< a search::Method name
  std::string network;  ///< relative to the plan's directory (or absolute); empty: no network
  double target = 0.0;
  double margin = 1.0;
  bool reached = false;
  PlanDomain domain;
  std::vector<PlanMeasurement> measurements;
};

/// Reads and checks `path` (header comment). IoError when it cannot be read; FormatError naming the file, the
/// line and the key for anything the format does not allow, including a method that search::Method::parse
/// refuses and a network given to a method without one or missing for a network method.
[[nodiscard]] ScenePlan read_plan(const std::filesystem::path& path);

/// The same for text (`source` names it in messages): for tests.
[[nodiscard]] ScenePlan parse_plan(const std::string& text, const std::string& source);

/// The plan as TOML text (comments included) that read_plan reads back to the same values (reals written with
/// 17 significant digits). InvalidArgument for a plan that read_plan would refuse.
[[nodiscard]] std::string plan_to_toml(const ScenePlan& plan);

/// The network file of `plan` read from `plan_path`: plan.network relative to the plan file's directory
/// (absolute as it is); empty when the plan has no network.
[[nodiscard]] std::filesystem::path plan_network_path(const ScenePlan& plan,
                                                      const std::filesystem::path& plan_path);

}  // namespace contactnn::io
