// Internal to lib/search: one block of W queries through a method, from the raw rows to the Results. Included
// by kernels_bilinear.cpp and kernels_gregory.cpp, which instantiate it per surface, input type, network type
// and block width (W = 1 is the path of queries outside whole blocks).
#pragma once

#include <cstdint>
#include <limits>
#include <type_traits>

#include "search/closed_form_block.hpp"
#include "search/network_block.hpp"
#include "search/newton_block.hpp"
#include "search/search_plan.hpp"
#include "search/surface_block.hpp"

namespace contactnn::search::detail {

template <bool kGregory, class Net, int W, class In>
void search_block(const Plan& plan, const In* raw_rows, const Results<In>& out, std::size_t first) {
  using Surf = std::conditional_t<kGregory, GregoryBlock<W>, BilinearBlock<W>>;
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr double kCentre = kGregory ? 0.5 : 0.0;
  const Method& method = plan.method;

  alignas(64) double raw[27][W];
  load_raw<W>(raw_rows + first * kStride, kStride, raw);
  QueryBlock<W> q;
  relative_queries<W>(raw, kGregory, q);
  LaneState<W> s;
  for (int l = 0; l < W; ++l) {
    s.u[l] = s.v[l] = kCentre;
    s.status[l] = q.finite[l] != 0.0 ? kOk : kInvalid;
    s.iterations[l] = 0.0;
  }

  Surf surf;
  bool built = false;
  const auto build = [&] {
    if (!built) surf.build(q, s.status);
    built = true;
  };
  const bool hybrid = method.is_hybrid();
  double extrapolated[W] = {};

  // 1. The start.
  if (method.start == Method::Start::kNetwork) {
    network_estimate<Net, W, kGregory>(*plan.network, plan.options.check_domain, &raw[0][0], s);
    if (hybrid) {
      // Newton decides the status. Without a canonical frame (a finite input) the network has no estimate: the
      // refinement starts from the domain centre. Outside its training domain the network extrapolates: its
      // estimate is still the start (near the domain it is good), but a refinement from it that fails is
      // retried from the centre (step 2).
      for (int l = 0; l < W; ++l) {
        extrapolated[l] = s.status[l] == kOutOfDomain ? 1.0 : 0.0;
        const bool none = s.status[l] == kDegenerate;
        s.u[l] = none ? kCentre : s.u[l];
        s.v[l] = none ? kCentre : s.v[l];
        s.status[l] = (none | (s.status[l] == kOutOfDomain)) ? kOk : s.status[l];
      }
    }
  } else if (method.start == Method::Start::kClosedForm) {
    if constexpr (!kGregory) {
      build();
      closed_form<W>(surf, s);
      if (hybrid) {
        for (int l = 0; l < W; ++l) s.status[l] = s.status[l] == kNoConvergence ? kOk : s.status[l];
      }
    }
  }

  // 2. Newton.
  EvalStore<W> store;
  if (hybrid) {
    build();
    double noise[W];
    for (int l = 0; l < W; ++l) {
      double size = 0.0;
      for (int k = 0; k < 12; ++k) size = std::fmax(size, std::fabs(q.node[k][l]));
      noise[l] = 16.0 * std::numeric_limits<double>::epsilon() * size;
    }
    safeguarded_newton<Surf, W>(surf, method.newton_steps, plan.guards, noise, s, store);
    bool retry = false;
    for (int l = 0; l < W; ++l) {
      extrapolated[l] = (extrapolated[l] != 0.0) & ((s.status[l] == kNoConvergence) | (s.status[l] == kDegenerate));
      retry = retry || extrapolated[l] != 0.0;
    }
    if (retry) {
      // Only the retried lanes run (the others are held by a status other than ok); their steps add up.
      LaneState<W> again;
      EvalStore<W> again_store;
      for (int l = 0; l < W; ++l) {
        again.u[l] = again.v[l] = kCentre;
        again.status[l] = extrapolated[l] != 0.0 ? kOk : kInvalid;
        again.iterations[l] = s.iterations[l];
      }
      safeguarded_newton<Surf, W>(surf, method.newton_steps, plan.guards, noise, again, again_store);
      for (int l = 0; l < W; ++l) {
        if (extrapolated[l] == 0.0) continue;
        s.u[l] = again.u[l];
        s.v[l] = again.v[l];
        s.status[l] = again.status[l];
        s.iterations[l] = again.iterations[l];
        for (int c = 0; c < 3; ++c) {
          store.p[c][l] = again_store.p[c][l];
          store.ps[c][l] = again_store.ps[c][l];
          store.pt[c][l] = again_store.pt[c][l];
        }
      }
    }
  } else if (method.start == Method::Start::kCentre) {
    build();
    if (method.to_convergence) {
      converged_newton<Surf, W>(surf, plan.options.max_iterations, plan.options.tol_param, s);
    } else {
      lean_newton<Surf, W>(surf, method.newton_steps, s);
    }
  }

  // 3. ok or outside by the domain (a network alone reports its own statuses).
  if (method.start != Method::Start::kNetwork || hybrid) {
    for (int l = 0; l < W; ++l) {
      const bool inside = s.u[l] >= plan.inside_lo && s.u[l] <= plan.inside_hi && s.v[l] >= plan.inside_lo &&
                          s.v[l] <= plan.inside_hi;
      s.status[l] = (s.status[l] == kOk && !inside) ? kOutside : s.status[l];
    }
  }

  // 4. The gap at the reported point.
  double gap[W];
  if (out.gap != nullptr) {
    if (hybrid) {
      for (int l = 0; l < W; ++l) {
        Eval e;
        store.load(l, e);
        gap[l] = gap_at(e);
      }
    } else {
      build();
      CONTACTNN_LANES
      for (int l = 0; l < W; ++l) {
        Eval e;
        surf.template eval<false>(l, s.u[l], s.v[l], e);
        gap[l] = gap_at(e);
      }
    }
    for (int l = 0; l < W; ++l) {
      const bool none = (s.status[l] == kInvalid) | (s.status[l] == kDegenerate);
      gap[l] = none ? 0.0 : gap[l];
    }
  }

  // 5. Out, never a NaN: a non-finite estimate (only possible from a network fed extreme values) is the centre.
  for (int l = 0; l < W; ++l) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    const bool finite = is_finite(s.u[l]) & is_finite(s.v[l]);
    out.param[2 * i] = static_cast<In>(finite ? s.u[l] : kCentre);
    out.param[2 * i + 1] = static_cast<In>(finite ? s.v[l] : kCentre);
    out.status[i] = static_cast<Status>(static_cast<int>(finite ? s.status[l] : kNoConvergence));
    if (out.iterations != nullptr) out.iterations[i] = static_cast<std::int32_t>(s.iterations[l]);
    if (out.gap != nullptr) out.gap[i] = static_cast<In>(gap[l]);
  }
}

/// The kernels of one surface kind: W lanes per block for the batched path, one lane for the rest.
template <bool kGregory>
void select_kernels(Plan& plan) {
  const bool float_network = plan.network != nullptr && plan.network->is_float();
  if (plan.method.needs_network() && float_network) {
    plan.block_size = 16;
    plan.block_f = &search_block<kGregory, float, 16, float>;
    plan.block_d = &search_block<kGregory, float, 16, double>;
    plan.single_f = &search_block<kGregory, float, 1, float>;
    plan.single_d = &search_block<kGregory, float, 1, double>;
  } else {
    plan.block_size = 8;
    plan.block_f = &search_block<kGregory, double, 8, float>;
    plan.block_d = &search_block<kGregory, double, 8, double>;
    plan.single_f = &search_block<kGregory, double, 1, float>;
    plan.single_d = &search_block<kGregory, double, 1, double>;
  }
}

}  // namespace contactnn::search::detail
