// What LocalSearch (segments) and FaceSearch (tri3, tri6, quad8 faces) do alike around their kernels: the
// checks of a method and its network, the fields every plan starts with, and the split of a run into blocks
// of lanes over OpenMP's threads. Internal to lib/search (local_search.cpp, face_search.cpp).
#pragma once

#include <omp.h>

#include <cstddef>
#include <memory>
#include <type_traits>

#include "core/error.hpp"
#include "search/method.hpp"
#include "search/search_options.hpp"

namespace contactnn::search::detail {

/// InvalidArgument for a step count out of range, or Newton to convergence from another start than the
/// centre.
inline void check_method_steps(const Method& method) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, method.newton_steps >= 0 && method.newton_steps <= Method::kMaxSteps,
                       "method " << method.name() << ": newton_steps = " << method.newton_steps
                                 << ", expected 0 to " << Method::kMaxSteps);
}

/// InvalidArgument unless a method that needs a network has one (`network`), made for `kind`
/// (kind_of(*network)); `faces` names what the search takes ("segments", "faces").
template <class Network, class Kind, class KindOf>
void check_network(const Method& method, const Network* network, Kind kind, KindOf kind_of,
                   const char* faces) {
  if (!method.needs_network()) return;
  CONTACTNN_REQUIRE_AS(InvalidArgument, network != nullptr, "method " << method.name() << " needs a network");
  CONTACTNN_REQUIRE_AS(InvalidArgument, kind_of(*network) == kind,
                       "method " << method.name() << " on " << to_string(kind) << " " << faces << " got a "
                                 << to_string(kind_of(*network)) << " network");
}

/// A plan with the fields every search has: the kind, the method, the (checked) options and the network, kept
/// only for a method that uses one.
template <class Plan, class Kind, class Network>
std::shared_ptr<Plan> new_plan(Kind kind, const Method& method, const SearchOptions& options,
                               const Network* network) {
  check_search_options(options);
  auto plan = std::make_shared<Plan>();
  plan->kind = kind;
  plan->method = method;
  plan->options = options;
  plan->network = method.needs_network() ? network : nullptr;
  return plan;
}

/// False for a run of no queries (nothing to do); InvalidArgument, naming the run (`who`), for a null array.
template <class Real, class Results>
bool queries_to_run(std::size_t count, const Real* raw, const Results& out, const char* who) {
  if (count == 0) return false;
  CONTACTNN_REQUIRE_AS(InvalidArgument, raw != nullptr && out.param != nullptr && out.status != nullptr,
                       who << ": raw, out.param and out.status must not be null for " << count << " queries");
  return true;
}

/// A plan's block kernel and one-lane kernel of one real type.
template <class Fn>
struct BlockKernels {
  Fn block, single;
};

/// The plan's kernels for the run's real type (its *_f or *_d).
template <class Real, class Plan>
auto block_kernels(const Plan& plan) {
  if constexpr (std::is_same_v<Real, float>) {
    return BlockKernels<decltype(plan.block_f)>{plan.block_f, plan.single_f};
  } else {
    return BlockKernels<decltype(plan.block_d)>{plan.block_d, plan.single_d};
  }
}

/// A run of `count` queries in blocks of `width` lanes: `blocks` whole ones, then the rest one lane at a
/// time; OpenMP's default team asked only of a run that may use it (a query alone, or a few, never does).
struct BlockSplit {
  BlockSplit(std::size_t count, int block_size, std::size_t min_parallel_count, int threads)
      : width(static_cast<std::size_t>(block_size)), blocks(count / width) {
    const bool large = blocks >= 2 && count >= min_parallel_count;
    team = !large ? 1 : (threads > 0 ? threads : omp_get_max_threads());
    parallel = team > 1;
  }

  /// block(first query) for every whole block, over the team when parallel.
  template <class Block>
  void each_block(const Block& block) const {
    if (parallel) {
      const auto n = static_cast<std::ptrdiff_t>(blocks);
#pragma omp parallel for num_threads(team) schedule(static)
      for (std::ptrdiff_t b = 0; b < n; ++b) block(static_cast<std::size_t>(b) * width);
    } else {
      for (std::size_t b = 0; b < blocks; ++b) block(b * width);
    }
  }

  /// single(query) for each query after the whole blocks.
  template <class Single>
  void each_rest(std::size_t count, const Single& single) const {
    for (std::size_t i = blocks * width; i < count; ++i) single(i);
  }

  std::size_t width, blocks;
  int team = 1;
  bool parallel = false;
};

}  // namespace contactnn::search::detail
