// Internal to lib/search: one block of W queries through a method, from the raw rows to the Results. Included
// by kernels_bilinear.cpp and kernels_gregory.cpp, which instantiate it per surface, input type, network type
// and block width (W = 1 is the path of queries outside whole blocks).
//
// The kernels' function templates here and in the *_block.hpp headers are `static`: each translation unit
// keeps the copies it compiled with its own flags (kernels_single.cpp without auto-vectorisation, the others
// with it). With external linkage the linker keeps one copy of each instantiation for the whole program: a
// width-independent one such as sigmoid_all<float> came from whichever object it saw first, and a benchmark
// that instantiated the block kernels in its own translation unit once replaced the library's (1.6-2x
// slower). The surface blocks' member functions keep external linkage; they are keyed on W, which no two of
// the kernel files share. tie_estimate is the one kernel meant to be shared (kernels_single.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "search/closed_form_block.hpp"
#include "search/four_triangles_block.hpp"
#include "search/network_block.hpp"
#include "search/newton_block.hpp"
#include "search/search_plan.hpp"
#include "search/surface_block.hpp"

namespace contactnn::search::detail {

/// A gap as the caller's type: one beyond the type's range is its largest value of the gap's sign (a finite
/// segment and slave node near FLT_MAX can be farther apart than FLT_MAX; a gap of a rescaled block,
/// multiplied back, can overflow near DBL_MAX; outputs are never infinite).
template <class In>
CONTACTNN_SEARCH_INLINE In gap_out(double gap) {
  constexpr double kLargest = std::numeric_limits<In>::max();
  return static_cast<In>(gap > kLargest ? kLargest : (gap < -kLargest ? -kLargest : gap));
}

/// A block with a node distance far from 1 (beyond 2^+-64, Surf::build says; or a lane whose nodes coincide):
/// its queries in units of each lane's segment size (rescale_queries) and the surface built again. Out of
/// line and cold: a real mesh's blocks come here only with a collapsed segment.
template <class Surf, int W>
[[gnu::noinline, gnu::cold]] static void rebuild_rescaled(Surf& surf, QueryBlock<W>& q,
                                                          double* patch_status) {
  rescale_queries<W>(q);
  for (int l = 0; l < W; ++l) patch_status[l] = kOk;
  (void)surf.build(q, patch_status);
}

/// The block's raw rows as doubles, a row per lane: rows first .. first + W - 1, or rows[0 .. W - 1].
template <int W, int kStride, class In>
CONTACTNN_SEARCH_INLINE static void load_rows(const In* raw_rows, std::size_t first, const std::size_t* rows,
                                              double (&raw)[27][W]) {
  if (rows == nullptr) {
    load_raw<W>(raw_rows + first * kStride, kStride, raw);
  } else {
    for (int l = 0; l < W; ++l) {
      const In* row = raw_rows + rows[l] * static_cast<std::size_t>(kStride);
      for (int k = 0; k < kStride; ++k) raw[k][l] = static_cast<double>(row[k]);
    }
  }
}

/// Step 1 with a network: its estimates; for a hybrid, the start Newton refines and the lanes retried from
/// the centre if that fails.
template <bool kGregory, class Net, int W>
CONTACTNN_SEARCH_INLINE static void network_start(const Plan& plan, double (&raw)[27][W], bool consecutive,
                                                  int cap, LaneState<W>& s, double* retry_from_centre) {
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr double kCentre = kGregory ? 0.5 : 0.0;
  // A float network's bilinear block: lanes the float frame does not decide are left pending for
  // LocalSearch::run (blocks of consecutive rows only; a one-lane kernel and a block of pending rows decide
  // every lane itself).
  const FramePass pass = cap == kDoubleFramePass                      ? FramePass::kDouble
                         : (W > 1 && consecutive && plan.defer_frame) ? FramePass::kFloatDeferred
                                                                      : FramePass::kFloat;
  network_estimate<Net, W, kGregory>(*plan.network, plan.options.check_domain, &raw[0][0], s, pass);
  if (!plan.method.is_hybrid()) return;
  // Newton decides the status. Where the network has no canonical frame, the segment is degenerate when
  // its label says so (degenerate_as_labelled: collapsed, or no frame at any corner; a collapsed segment
  // refined from the centre came back ok); otherwise (a Gregory node normal on the far side of the
  // canonical corner's plane, where another corner has a frame) the refinement starts from the domain
  // centre. Outside its training domain the network extrapolates: its estimate is still the start (near
  // the domain it is good), but a refinement from it that fails is retried from the centre (step 2).
  for (int l = 0; l < W; ++l) {
    retry_from_centre[l] = s.status[l] == kOutOfDomain ? 1.0 : 0.0;
    bool none = false;
    if (s.status[l] == kDegenerate) {
      double query[27];
      for (int k = 0; k < kStride; ++k) query[k] = raw[k][l];
      none = !degenerate_as_labelled(query, kGregory);
    }
    s.u[l] = none ? kCentre : s.u[l];
    s.v[l] = none ? kCentre : s.v[l];
    s.status[l] = (none | (s.status[l] == kOutOfDomain)) ? kOk : s.status[l];
  }
}

/// Step 1 with the closed form on a Gregory patch: the closed form on the bilinear facet of its corner nodes,
/// (u, v) = ((xi + 1) / 2, (eta + 1) / 2), exact where the patch is that facet (a flat segment whose node
/// normals are its normal, SPEC 1). A collapsed facet is degenerate, as the labels say: the patch's build
/// tested it (collapsed_segment), and q's range (rescaled if it had to be).
/// The estimate goes to the patch's canonical parametrisation (its LaneSymmetry, chosen from the same corner
/// facet; exact in (xi, eta)), to (u, v) there, and is reported through the patch, which keeps it, so that
/// the gap is evaluated at the same point in every node order (from the caller's u, the reflection 1 - u
/// rounds, and a far slave's extrapolated gap moved by 1e-6 of itself with the node order). A lane the closed
/// form did not answer (degenerate, invalid) keeps the centre.
template <int W>
CONTACTNN_SEARCH_INLINE static void gregory_closed_form(const QueryBlock<W>& q, GregoryBlock<W>& surf,
                                                        LaneState<W>& s, bool hybrid) {
  BilinearBlock<W> facet;
  (void)facet.template build<false>(q, nullptr);
  double answered[W];
  for (int l = 0; l < W; ++l) answered[l] = s.status[l] == kOk ? 1.0 : 0.0;
  closed_form<W>(facet, s, hybrid);
  for (int l = 0; l < W; ++l) {
    double xi = s.u[l], eta = s.v[l];
    surf.sym.template to_canonical<BilinearBlock<W>::kReflect>(l, xi,
                                                               eta);  // the patch's: exact in (xi, eta)
    double u = 0.5 * (xi + 1.0), v = 0.5 * (eta + 1.0);
    surf.report(l, u, v);
    const bool take = (answered[l] != 0.0) & (s.status[l] != kDegenerate);
    s.u[l] = take ? u : s.u[l];
    s.v[l] = take ? v : s.v[l];
  }
}

/// Step 1 with the caller's start: its row of the param array the results go to (each lane's row is read
/// here, before any row of the block is written). A start that is not finite: invalid.
template <int W, class In>
CONTACTNN_SEARCH_INLINE static void given_start(const Results<In>& out, std::size_t first,
                                                const std::size_t* rows, double centre, LaneState<W>& s) {
  for (int l = 0; l < W; ++l) {
    const std::size_t i = rows == nullptr ? first + static_cast<std::size_t>(l) : rows[l];
    const auto u = static_cast<double>(out.param[2 * i]), v = static_cast<double>(out.param[2 * i + 1]);
    const bool finite = is_finite(u) & is_finite(v);
    s.u[l] = finite ? u : centre;
    s.v[l] = finite ? v : centre;
    s.status[l] = finite ? s.status[l] : kInvalid;
  }
}

/// Step 2 of a hybrid, its second run: the lanes retry_from_centre marks run again from the centre (the
/// others are held by a status other than ok; their steps add up), and the centre's answer replaces the first
/// where it should.
template <bool kGregory, class Surf, int W>
CONTACTNN_SEARCH_INLINE static void newton_again_from_centre(const Plan& plan, Surf& surf,
                                                             const double* noise,
                                                             const double* retry_from_centre, LaneState<W>& s,
                                                             EvalStore<W, Surf::kHasPureSecond>& store) {
  constexpr double kCentre = kGregory ? 0.5 : 0.0;
  LaneState<W> again;
  EvalStore<W, Surf::kHasPureSecond> again_store;
  for (int l = 0; l < W; ++l) {
    again.u[l] = again.v[l] = kCentre;
    again.status[l] = retry_from_centre[l] != 0.0 ? kOk : kInvalid;
    again.iterations[l] = s.iterations[l];
  }
  safeguarded_newton<Surf, W>(surf, plan.method.newton_steps, plan.guards, noise, again, again_store);
  for (int l = 0; l < W; ++l) {
    if (retry_from_centre[l] == 0.0) continue;
    // An answer at the edge stays unless the centre's is inside and nearer S (after few steps the centre's
    // run may be on its way, not there: an interior point farther than the edge is no better answer).
    const bool edge_stays = (again.status[l] != kOk) | !(again_store.dist[l] < store.dist[l]);
    if (s.status[l] == kOutside && edge_stays) {  // the steps of both runs
      s.iterations[l] = again.iterations[l];
      continue;
    }
    s.u[l] = again.u[l];
    s.v[l] = again.v[l];
    s.status[l] = again.status[l];
    s.iterations[l] = again.iterations[l];
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      store.p[c][l] = again_store.p[c][l];
      store.ps[c][l] = again_store.ps[c][l];
      store.pt[c][l] = again_store.pt[c][l];
    }
  }
}

/// Step 2 of a hybrid: safeguarded Newton from the start, and from the centre again where that failed.
/// Lanes whose refinement, if it fails, is retried from the centre (retry_from_centre): on a Gregory patch
/// every lane that starts from an estimate; on a bilinear facet a network's estimate outside its training
/// domain only (network_start marks them: from the centre, plain Newton itself ends at another stationary
/// point of a warped facet, inside the larger box, as often as not: on 100000 held-out configurations
/// retrying every failure turned 62 failures of closed_form+newton:1 into answers, some of them wrong and
/// reported ok).
template <bool kGregory, class Surf, int W>
CONTACTNN_SEARCH_INLINE static void hybrid_newton(const Plan& plan, const QueryBlock<W>& q, Surf& surf,
                                                  double* retry_from_centre, LaneState<W>& s,
                                                  EvalStore<W, Surf::kHasPureSecond>& store) {
  constexpr double kCentre = kGregory ? 0.5 : 0.0;
  double noise[W];
  for (int l = 0; l < W; ++l) {
    double size = 0.0;
    CONTACTNN_UNROLL
    for (int k = 0; k < 12; ++k) size = max_of(size, std::fabs(q.node[k][l]));
    noise[l] = 16.0 * std::numeric_limits<double>::epsilon() * size;
  }
  if constexpr (kGregory) {
    for (int l = 0; l < W; ++l) {
      const bool estimate = (s.status[l] == kOk) & ((s.u[l] != kCentre) | (s.v[l] != kCentre));
      retry_from_centre[l] = estimate ? 1.0 : 0.0;
    }
  }
  safeguarded_newton<Surf, W>(surf, plan.method.newton_steps, plan.guards, noise, s, store);
  bool retry = false;
  for (int l = 0; l < W; ++l) {
    // On a Gregory patch an answer at the edge (outside) is checked from the centre too: a start in another
    // basin slides along the edge to a point where the distance falls outward while an interior stationary
    // point, the answer by SPEC 2, lies elsewhere. The centre's answer replaces it only when ok and nearer.
    const bool failed = (s.status[l] == kNoConvergence) | (s.status[l] == kDegenerate) |
                        (kGregory & (s.status[l] == kOutside));
    retry_from_centre[l] = (retry_from_centre[l] != 0.0) & failed ? 1.0 : 0.0;
    retry = retry || retry_from_centre[l] != 0.0;
  }
  // A start in another basin: on a Gregory sliver a network estimate 0.5 off sends the descent to the edge
  // of the segment, where it fails or stops at an edge point, while the reference's nearest local minimum
  // lies inside (held-out sets of 100000: 1 such failure in 4 sets of network+newton:3, none after the
  // retry).
  if (retry) newton_again_from_centre<kGregory, Surf, W>(plan, surf, noise, retry_from_centre, s, store);
}

/// Every lane at the centre, ok, no iterations.
template <int W>
CONTACTNN_SEARCH_INLINE static void start_at_centre(double centre, LaneState<W>& s) {
  for (int l = 0; l < W; ++l) {
    s.u[l] = s.v[l] = centre;
    s.status[l] = kOk;
    s.iterations[l] = 0.0;
  }
}

/// Step 3: an ok lane whose (u, v) lies outside [lo, hi]^2 is outside.
template <int W>
CONTACTNN_SEARCH_INLINE static void outside_by_domain(double lo, double hi, LaneState<W>& s) {
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const bool inside = (s.u[l] >= lo) & (s.u[l] <= hi) & (s.v[l] >= lo) & (s.v[l] <= hi);
    s.status[l] = ((s.status[l] == kOk) & !inside) ? kOutside : s.status[l];
  }
}

/// Step 4: the gap at the reported point of each lane, in world units: from Newton's last evaluation
/// (`hybrid`), as the method gave it (`given`: four_triangles), else evaluated on the surface (built).
/// An invalid or degenerate lane's gap is 0.
template <int W, class Surf, class Store>
CONTACTNN_SEARCH_INLINE static void block_gaps(bool hybrid, const double* given, const Store& store,
                                               const QueryBlock<W>& q, const Surf& surf,
                                               const LaneState<W>& s, const double* patch_status,
                                               double* gap) {
  if (hybrid) {
    for (int l = 0; l < W; ++l) {
      Eval e;
      store.load(l, e);
      gap[l] = gap_at(e);
    }
  } else if (given != nullptr) {
    for (int l = 0; l < W; ++l) gap[l] = given[l];
  } else {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      Eval e;
      surf.template eval<false>(l, s.u[l], s.v[l], e);
      gap[l] = gap_at(e);
    }
  }
  for (int l = 0; l < W; ++l) {
    const bool none = (s.status[l] == kInvalid) | (s.status[l] == kDegenerate) | (patch_status[l] != kOk);
    gap[l] = none ? 0.0 : gap[l];
  }
  if (q.scaled) {
    // In world units (rescale_queries); beyond the double range (nodes near 1e308) gap_out caps it.
    for (int l = 0; l < W; ++l) gap[l] *= q.unit[l];
  }
}

/// Step 5: the lanes out, never a NaN: a non-finite estimate (only possible from a network fed extreme
/// values) is the centre. Computed over the lanes first, then stored: the stores of a whole block are loops
/// GCC vectorises (the pairs interleaved, the status narrowed to a byte).
template <int W, class In>
CONTACTNN_SEARCH_INLINE static void write_lanes(const LaneState<W>& s, const double* gap, double centre,
                                                const Results<In>& out, std::size_t first,
                                                const std::size_t* rows) {
  alignas(64) In pu[W], pv[W];
  alignas(64) std::int32_t ps[W], pi[W];
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const bool finite = is_finite(s.u[l]) & is_finite(s.v[l]);
    pu[l] = static_cast<In>(finite ? s.u[l] : centre);
    pv[l] = static_cast<In>(finite ? s.v[l] : centre);
    ps[l] = static_cast<std::int32_t>(finite ? s.status[l] : kNoConvergence);
    pi[l] = static_cast<std::int32_t>(s.iterations[l]);
  }
  if (rows == nullptr) {
    In* param = out.param + 2 * first;
    Status* status = out.status + first;
#pragma omp simd
    for (int l = 0; l < W; ++l) {
      param[2 * l] = pu[l];
      param[2 * l + 1] = pv[l];
    }
#pragma omp simd
    for (int l = 0; l < W; ++l) status[l] = static_cast<Status>(ps[l]);
    if (out.iterations != nullptr) std::copy(pi, pi + W, out.iterations + first);
    if (out.gap != nullptr) {
      In* g = out.gap + first;
#pragma omp simd
      for (int l = 0; l < W; ++l) g[l] = gap_out<In>(gap[l]);
    }
  } else {
    for (int l = 0; l < W; ++l) {
      const std::size_t i = rows[l];
      out.param[2 * i] = pu[l];
      out.param[2 * i + 1] = pv[l];
      out.status[i] = static_cast<Status>(ps[l]);
      if (out.iterations != nullptr) out.iterations[i] = pi[l];
      if (out.gap != nullptr) out.gap[i] = gap_out<In>(gap[l]);
    }
  }
}

/// One block of W queries: rows first .. first + W - 1 of raw_rows, or (rows not null) the rows rows[0 .. W -
/// 1], in any order, repeats allowed. cap > 0 (Newton to convergence only): at most cap iterations, a lane
/// still running then gets status kPending (LocalSearch::run computes it again, from the centre, in a block
/// of such lanes with the next cap or none).
template <bool kGregory, class Net, int W, class In>
static void search_rows(const Plan& plan, const In* raw_rows, const Results<In>& out, std::size_t first,
                        const std::size_t* rows, int cap) {
  using Surf = std::conditional_t<kGregory, GregoryBlock<W>, BilinearBlock<W>>;
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr double kCentre = kGregory ? 0.5 : 0.0;
  const Method& method = plan.method;

  alignas(64) double raw[27][W];
  load_rows<W, kStride>(raw_rows, first, rows, raw);
  // The queries relative to S, for the surface: made when a method needs the surface (not by a network alone
  // without the gap, whose canonical frame works on the raw coordinates and finds non-finite inputs itself).
  QueryBlock<W> q;
  LaneState<W> s;
  start_at_centre<W>(kCentre, s);
  bool relative = false;
  const auto make_relative = [&] {
    if (relative) return;
    relative_queries<W>(raw, kGregory, q);
    // Invalid where an input is not finite (lanes a network already marked keep their status).
    for (int l = 0; l < W; ++l) s.status[l] = q.finite[l] != 0.0 ? s.status[l] : kInvalid;
    relative = true;
  };
  if (method.start != Method::Start::kNetwork) make_relative();

  // The surface, built once. Where it does not exist (a Gregory patch GregoryPatch::diagnose refuses),
  // patch_status is degenerate; the methods that work on the surface take that status over.
  Surf surf;
  double patch_status[W];
  bool built = false;
  const auto build = [&] {
    make_relative();
    if (built) return;
    for (int l = 0; l < W; ++l) patch_status[l] = kOk;
    if (surf.build(q, patch_status)) rebuild_rescaled<Surf, W>(surf, q, patch_status);
    built = true;
  };
  const auto build_for_method = [&] {
    build();
    for (int l = 0; l < W; ++l)
      s.status[l] = (s.status[l] == kOk) & (patch_status[l] != kOk) ? kDegenerate : s.status[l];
  };
  const bool hybrid = method.is_hybrid();
  double retry_from_centre[W] = {};  // lanes retried from the centre if they fail (hybrid_newton)
  double triangles_gap[W] = {};      // four_triangles: its gap, in q's units

  // 1. The start.
  if (method.start == Method::Start::kNetwork) {
    network_start<kGregory, Net, W>(plan, raw, rows == nullptr, cap, s, retry_from_centre);
  } else if (method.start == Method::Start::kClosedForm) {
    build_for_method();
    if constexpr (!kGregory) {
      closed_form<W>(surf, s, hybrid);
    } else {
      gregory_closed_form<W>(q, surf, s, hybrid);
    }
    if (hybrid) {
      for (int l = 0; l < W; ++l) s.status[l] = s.status[l] == kNoConvergence ? kOk : s.status[l];
    }
  } else if (method.start == Method::Start::kFourTriangles) {
    // The four triangles about the centroid (bilinear only: LocalSearch refuses a Gregory kind). The status
    // (ok or outside) and the gap are the method's own.
    if constexpr (!kGregory) {
      build_for_method();
      four_triangles<W>(q, surf, plan.options.domain_margin, s, triangles_gap);
    }
  } else if (method.start == Method::Start::kGiven) {
    build_for_method();
    given_start<W>(out, first, rows, kCentre, s);
  }

  // 2. Newton.
  EvalStore<W, Surf::kHasPureSecond> store;
  if (hybrid) {
    build_for_method();
    hybrid_newton<kGregory, Surf, W>(plan, q, surf, retry_from_centre, s, store);
  } else if (method.start == Method::Start::kCentre) {
    build_for_method();
    if (method.to_convergence) {
      converged_newton<Surf, W>(surf, cap > 0 ? cap : plan.options.max_iterations, plan.options.tol_param,
                                cap > 0, s);
    } else {
      lean_newton<Surf, W>(surf, method.newton_steps, s);
    }
  }

  // 3. ok or outside by the domain (a network alone and four_triangles report their own statuses).
  if ((method.start != Method::Start::kNetwork && method.start != Method::Start::kFourTriangles) || hybrid) {
    outside_by_domain<W>(plan.inside_lo, plan.inside_hi, s);
  }

  // 4. The gap at the reported point.
  double gap[W];
  if (out.gap != nullptr) {
    const double* given = method.start == Method::Start::kFourTriangles ? triangles_gap : nullptr;
    if (!hybrid && given == nullptr) build();
    block_gaps<W>(hybrid, given, store, q, surf, s, patch_status, gap);
  }

  // 5. Out.
  write_lanes<W>(s, gap, kCentre, out, first, rows);
}

/// search_rows for the rows first .. first + W - 1, no cap: the BlockFn of a plan.
template <bool kGregory, class Net, int W, class In>
static void search_block(const Plan& plan, const In* raw_rows, const Results<In>& out, std::size_t first) {
  search_rows<kGregory, Net, W, In>(plan, raw_rows, out, first, nullptr, 0);
}

/// The block kernels of one surface kind. Widths measured on AVX-512 (scripts/bench-search): wider blocks
/// give each vector operation several independent vectors to overlap, up to the register file: a float
/// network 32 lanes (its 8 accumulators of 32 floats fill 16 of the 32 vector registers), a double network
/// 16; lean and safeguarded Newton and the closed form 32 (12.3 ns for newton:5 against 15.5 at 16 and 24.7
/// at 8); four_triangles 32 (its time over newton:5's 1.9 at 32 and at 16, within the noise); Newton to
/// convergence 16, since a block iterates until its slowest lane has converged.
template <bool kGregory>
static void select_block_kernels(Plan& plan) {
  const bool network = plan.method.needs_network();
  if (network && plan.network->is_float()) {
    plan.block_size = 32;
    plan.block_f = &search_block<kGregory, float, 32, float>;
    plan.block_d = &search_block<kGregory, float, 32, double>;
    if constexpr (!kGregory) {
      plan.rows_f = &search_rows<kGregory, float, 32, float>;
      plan.rows_d = &search_rows<kGregory, float, 32, double>;
      plan.defer_frame = true;
    }
  } else if (network || plan.method.to_convergence) {
    plan.block_size = 16;
    plan.block_f = &search_block<kGregory, double, 16, float>;
    plan.block_d = &search_block<kGregory, double, 16, double>;
    if (plan.method.to_convergence) {
      plan.rows_f = &search_rows<kGregory, double, 16, float>;
      plan.rows_d = &search_rows<kGregory, double, 16, double>;
    }
  } else {
    plan.block_size = 32;
    plan.block_f = &search_block<kGregory, double, 32, float>;
    plan.block_d = &search_block<kGregory, double, 32, double>;
  }
}

/// network_stages (search_plan.hpp) for one surface, network type and block width.
template <bool kGregory, class Net, int W>
static double network_stages_of(const NetworkModel& model, const double* raw_rows, std::size_t count,
                                int stage, std::size_t& done) {
  constexpr int kStride = kGregory ? 27 : 15;
  constexpr int kG = kGregory ? 1 : 0;
  const std::size_t blocks = count / W;
  double sink = 0.0;
  for (std::size_t b = 0; b < blocks; ++b) {
    alignas(64) double raw[27][W];
    load_raw<W>(raw_rows + b * W * kStride, kStride, raw);
    if (stage <= 1) {
      sink += raw[0][0] + raw[kStride - 1][W - 1];
    } else if (stage >= 4) {
      LaneState<W> lanes;
      network_estimate<Net, W, kGregory>(model, true, &raw[0][0], lanes, FramePass::kFloatDeferred);
      sink += lanes.u[0] + lanes.v[W - 1];
    } else {
      alignas(64) double features[16 * W], normals[12 * W], info[CNN_CF_INFO_ROWS * W];
      if constexpr (!kGregory &&
                    sizeof(Net) == sizeof(float)) {  // as network_estimate, the undecided lanes left
        sink += cnn_cff_block(W, stage >= 3 ? &model.domain_bounds() : nullptr, &raw[0][0], features, info);
      } else {
        cnn_canonicalise_block(W, kG, &raw[0][0], features, normals, info);
        if (stage >= 3) cnn_domain_block(W, kG, &model.domain_bounds(), features, normals, info);
      }
      sink += features[0] + info[W - 1];
    }
  }
  done = blocks * W;
  return sink;
}

template <bool kGregory>
static double network_stages_for(const NetworkModel& model, const double* raw, std::size_t count, int stage,
                                 std::size_t& done) {
  // The widths of select_block_kernels.
  return model.is_float() ? network_stages_of<kGregory, float, 32>(model, raw, count, stage, done)
                          : network_stages_of<kGregory, double, 16>(model, raw, count, stage, done);
}

/// The one-lane kernels (kernels_single.cpp, compiled without auto-vectorisation: with it, GCC vectorises
/// other loops of a one-lane kernel than the lane loops of a block, e.g. a layer's sum over inputs, and the
/// changed contraction of multiply-adds changes the last bits; without it every statement rounds as in the
/// vectorised lane loops, so a query gives the same bits in a block and alone).
void select_single_kernels(Plan& plan);

}  // namespace contactnn::search::detail
