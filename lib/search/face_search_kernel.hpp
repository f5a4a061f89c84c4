// Internal to lib/search: one block of W queries of FaceSearch through its method, from the raw rows to the
// Results. Included by face_kernels.cpp (the blocks, vectorised) and face_kernels_single.cpp (W = 1, compiled
// without auto-vectorisation, so that a query alone rounds as a lane of a block: kernels_single.cpp's
// reason).
#pragma once

#include <algorithm>
#include <cmath>

#include "search/face_block.hpp"
#include "search/face_network_block.hpp"
#include "search/search_kernel.hpp"

namespace contactnn::search::detail {

/// One block of W queries (rows first .. first + W - 1) through the plan's method.
template <int kFace, int W, class In>
static void face_block(const FacePlan& plan, const In* raw_rows, const Results<In>& out, std::size_t first) {
  using T = FaceTraits<kFace>;
  const Method& method = plan.method;
  alignas(64) double raw[T::kStride][W];
  load_raw<W>(raw_rows + first * T::kStride, T::kStride, raw);
  FaceBlock<kFace, W> f;
  f.build(raw);
  LaneState<W> s;
  for (int l = 0; l < W; ++l) {
    s.u[l] = s.v[l] = T::kCentre;
    s.status[l] = f.status[l];
    s.iterations[l] = 0.0;
  }

  // 1. The start, 2. Newton.
  switch (method.start) {
    case Method::Start::kCentre:
      face_plain_newton<kFace, W>(f,
                                  method.to_convergence ? plan.options.max_iterations : method.newton_steps,
                                  method.to_convergence, plan.options.tol_param, s);
      break;
    case Method::Start::kClosedForm: face_closed_form<kFace, W>(f, s); break;
    case Method::Start::kGiven:
      for (int l = 0; l < W; ++l) {
        const std::size_t i = first + static_cast<std::size_t>(l);
        const auto u = static_cast<double>(out.param[2 * i]), v = static_cast<double>(out.param[2 * i + 1]);
        const bool finite = is_finite(u) & is_finite(v);
        s.u[l] = finite ? u : T::kCentre;
        s.v[l] = finite ? v : T::kCentre;
        s.status[l] = finite ? s.status[l] : kInvalid;
      }
      break;
    case Method::Start::kNetwork:
      face_network_estimate<kFace, W>(*plan.network, plan.options.check_domain, raw, s);
      break;
    case Method::Start::kFourTriangles: break;  // refused by FaceSearch
  }
  const bool hybrid = method.is_hybrid();
  if (hybrid) {
    // The start decides nothing: a closed form beyond the fold and a network's query outside its domain are
    // still starts (a degenerate or invalid lane stays so).
    for (int l = 0; l < W; ++l) {
      s.status[l] = (s.status[l] == kNoConvergence) | (s.status[l] == kOutOfDomain) ? kOk : s.status[l];
    }
    face_safeguarded_newton<kFace, W>(f, plan, method.newton_steps, s);
  }

  // 3. ok or outside by the domain (a network alone reports its own statuses).
  if (method.start != Method::Start::kNetwork || hybrid) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const bool inside = face_inside<kFace>(s.u[l], s.v[l], plan.options.domain_margin);
      s.status[l] = (s.status[l] == kOk) & !inside ? kOutside : s.status[l];
    }
  }

  // 4. The gap n.(S - P) at the reported point, in world units, never larger than S's distance to the face's
  //    nearest node (a slave far from a curved face has its stationary point on the surface's extrapolation,
  //    whose gap grows with the distance squared).
  double gap[W];
  if (out.gap != nullptr) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      Eval e;
      f.template eval<false>(l, s.u[l], s.v[l], e);
      const double n[3] = {e.ps[1] * e.pt[2] - e.ps[2] * e.pt[1], e.ps[2] * e.pt[0] - e.ps[0] * e.pt[2],
                           e.ps[0] * e.pt[1] - e.ps[1] * e.pt[0]};
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      const double g = -(n[0] * e.p[0] + n[1] * e.p[1] + n[2] * e.p[2]) / length;
      const bool none =
          (s.status[l] == kInvalid) | (s.status[l] == kDegenerate) | !(length > 0.0) | !is_finite(g);
      const double capped = g > f.nearest[l] ? f.nearest[l] : (g < -f.nearest[l] ? -f.nearest[l] : g);
      gap[l] = none ? 0.0 : capped * f.unit[l];
    }
  }

  // 5. Out, never a NaN.
  for (int l = 0; l < W; ++l) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    const bool finite = is_finite(s.u[l]) & is_finite(s.v[l]);
    out.param[2 * i] = static_cast<In>(finite ? s.u[l] : T::kCentre);
    out.param[2 * i + 1] = static_cast<In>(finite ? s.v[l] : T::kCentre);
    out.status[i] = static_cast<Status>(static_cast<int>(finite ? s.status[l] : kNoConvergence));
    if (out.iterations != nullptr) out.iterations[i] = static_cast<std::int32_t>(s.iterations[l]);
    if (out.gap != nullptr) out.gap[i] = gap_out<In>(gap[l]);
  }
}

/// The one-lane kernels (face_kernels_single.cpp).
void select_face_single_kernels(FacePlan& plan);

}  // namespace contactnn::search::detail
