#include "search/local_search.hpp"

#include <omp.h>

#include <algorithm>
#include <iterator>
#include <type_traits>

#include "core/error.hpp"
#include "search/face_boundary.hpp"
#include "search/search_plan.hpp"
#include "search/search_run.hpp"

namespace contactnn::search {

LocalSearch::LocalSearch(SurfaceKind kind, Method method, SearchOptions options,
                         const NetworkModel* network) {
  detail::check_method_steps(method);
  if (method.start == Method::Start::kFourTriangles) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, kind == SurfaceKind::kBilinear,
                         "method four_triangles splits a bilinear segment; it has no form for "
                             << to_string(kind) << " segments");
    CONTACTNN_REQUIRE_AS(InvalidArgument, method.newton_steps == 0 && !method.to_convergence,
                         "method four_triangles takes no Newton steps; got " << method.name());
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, !method.to_convergence || method.start == Method::Start::kCentre,
                       "Newton to convergence starts from the centre; got start " << method.name());
  detail::check_network(
      method, network, kind, [](const NetworkModel& n) { return n.surface(); }, "segments");

  auto plan = detail::new_plan<detail::Plan>(kind, method, options, network);
  const ParamDomain d = param_domain(kind);
  const double width = d.hi - d.lo;
  const double box = kind == SurfaceKind::kGregory ? options.gregory_box_margin : options.bilinear_box_margin;
  plan->inside_lo = d.lo - options.domain_margin;
  plan->inside_hi = d.hi + options.domain_margin;
  plan->guards = detail::Safeguards{d.lo - box * width, d.hi + box * width,   options.max_step_widths * width,
                                    options.tol_param,  options.max_halvings, plan->inside_lo,
                                    plan->inside_hi};
  // Every kernel of the plan from one variant (isa_dispatch.hpp): the block and the one-lane kernels round
  // alike.
  const detail::IsaKernels& kernels = detail::isa_kernels(kernel_isa());
  plan->isa = kernels.isa;
  if (kind == SurfaceKind::kGregory) {
    kernels.select_gregory(*plan);
  } else {
    kernels.select_bilinear(*plan);
  }
  plan_ = std::move(plan);
}

SurfaceKind LocalSearch::surface() const { return plan_->kind; }
const Method& LocalSearch::method() const { return plan_->method; }
const SearchOptions& LocalSearch::options() const { return plan_->options; }
const NetworkModel* LocalSearch::network() const { return plan_->network; }
int LocalSearch::block_size() const { return plan_->block_size; }

namespace {

/// The whole face (SearchOptions::closest_point_on_face): answers outside go to the boundary; the others pay
/// a byte compare in a tight loop (the branch is rarely taken). Each query's own arithmetic: the same bits in
/// any batch.
template <class Real>
void to_face_boundary(const detail::Plan& plan, std::size_t count, const Real* raw,
                      const Results<Real>& out) {
  if (out.location != nullptr) std::fill(out.location, out.location + count, Location::kFace);
  if (plan.options.closest_point_on_face) {
    const auto columns = static_cast<std::size_t>(LocalSearch::raw_columns(plan.kind));
    const auto move = [&](std::size_t i) {
      detail::move_to_face_boundary(plan.kind, raw + i * columns, out.param + 2 * i,
                                    out.gap != nullptr ? out.gap + i : nullptr, out.status + i,
                                    out.location != nullptr ? out.location + i : nullptr);
    };
    for (std::size_t i = 0; i < count; ++i) {
      if (out.status[i] == Status::kOutside) [[unlikely]]
        move(i);
    }
  }
}

}  // namespace

template <class Real>
void LocalSearch::run(std::size_t count, const Real* raw, const Results<Real>& out, int threads) const {
  if (!detail::queries_to_run(count, raw, out, "LocalSearch::run")) return;
  const detail::Plan& plan = *plan_;
  const auto kernels = detail::block_kernels<Real>(plan);
  const auto block = kernels.block, single = kernels.single;
  const detail::BlockSplit split(count, plan.block_size, plan.options.min_parallel_count, threads);
  const std::size_t width = split.width, blocks = split.blocks;
  const int team = split.team;
  const bool parallel = split.parallel;
  detail::RowsFn<Real> rows = nullptr;
  if constexpr (std::is_same_v<Real, float>) {
    rows = plan.rows_f;
  } else {
    rows = plan.rows_d;
  }
  // The rows among blocks b0 .. b1 - 1 left pending by a pass, computed again by `rows` with `cap`, in blocks
  // of such rows (the last one padded with repeats: the same bits twice).
  const auto recompute_pending = [&](std::size_t b0, std::size_t b1, int cap) {
    std::size_t group[detail::kMaxBlockSize];
    std::size_t filled = 0;
    for (std::size_t i = b0 * width; i < b1 * width; ++i) {
      if (out.status[i] != detail::kPendingStatus) continue;
      group[filled++] = i;
      if (filled == width) {
        rows(plan, raw, out, 0, group, cap);
        filled = 0;
      }
    }
    if (filled > 0) {
      for (std::size_t k = filled; k < width; ++k) group[k] = group[filled - 1];
      rows(plan, raw, out, 0, group, cap);
    }
  };
  // `passes` over each thread's share of the blocks (all of them on one thread when not parallel).
  const auto per_thread = [&](const auto& passes) {
    if (parallel) {
#pragma omp parallel num_threads(team)
      {
        const auto t = static_cast<std::size_t>(omp_get_thread_num());
        const auto n = static_cast<std::size_t>(omp_get_num_threads());
        passes(blocks * t / n, blocks * (t + 1) / n);
      }
    } else {
      passes(0, blocks);
    }
  };
  if (plan.defer_frame) {
    // A float network on bilinear segments: each block decides in float the lanes whose canonical frame float
    // decides (98 in 100 of random queries of the paper's domain) and leaves the others pending; those are
    // computed again with the frame in double, gathered into blocks of such lanes (each thread its own),
    // instead of a double pass in every block for its one or two. A lane's arithmetic does not depend on its
    // block: the results are those of FramePass::kFloat, bit for bit.
    per_thread([&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) block(plan, raw, out, b * width);
      recompute_pending(b0, b1, detail::kDoubleFramePass);
    });
  } else if (rows != nullptr && plan.options.max_iterations > detail::kPassCaps[0]) {
    // Newton to convergence: a block iterates until its slowest lane stops, and the iterations a lane needs
    // are long-tailed (random bilinear queries: mean 8.5, but 28 for the slowest of 16, and 1.4% run to the
    // limit of 50). So every block stops at the first pass's cap, and the lanes still running are computed
    // again from the centre in blocks of such lanes (each thread its own), up to the next cap, and so on. A
    // lane's arithmetic does not depend on its block, so the results are those of one pass, bit for bit.
    per_thread([&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) rows(plan, raw, out, b * width, nullptr, detail::kPassCaps[0]);
      for (std::size_t p = 1; p < std::size(detail::kPassCaps) + 1; ++p) {
        const int cap = p < std::size(detail::kPassCaps) && detail::kPassCaps[p] < plan.options.max_iterations
                            ? detail::kPassCaps[p]
                            : 0;
        recompute_pending(b0, b1, cap);
        if (cap == 0) break;
      }
    });
  } else {
    split.each_block([&](std::size_t first) { block(plan, raw, out, first); });
  }
  split.each_rest(count, [&](std::size_t i) { single(plan, raw, out, i); });

  to_face_boundary(plan, count, raw, out);
}

namespace detail {

double network_stages(const NetworkModel& model, const double* raw, std::size_t count, int stage,
                      std::size_t& done) {
  const IsaKernels& kernels = isa_kernels(kernel_isa());
  return model.surface() == SurfaceKind::kGregory
             ? kernels.network_stages_gregory(model, raw, count, stage, done)
             : kernels.network_stages_bilinear(model, raw, count, stage, done);
}

}  // namespace detail

template void LocalSearch::run<float>(std::size_t, const float*, const Results<float>&, int) const;
template void LocalSearch::run<double>(std::size_t, const double*, const Results<double>&, int) const;

}  // namespace contactnn::search
