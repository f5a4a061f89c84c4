// Internal to lib/search: what a LocalSearch fixed at construction, and the block kernels it dispatches to.
#pragma once

#include <cstddef>

#include "search/isa_dispatch.hpp"
#include "search/local_search.hpp"
#include "search/newton_block.hpp"

namespace contactnn::search::detail {

/// The widest block of any kernel (select_block_kernels).
inline constexpr int kMaxBlockSize = 32;
/// Newton to convergence: the iteration caps of LocalSearch::run's passes (the last pass has none). From the
/// iterations random bilinear queries need (LocalSearch::run), the passes cost a block of 16 lanes, in
/// iterations per query: one pass 28.0; caps 10 then none 16.9; 8, 20, then none 14.8.
inline constexpr int kPassCaps[] = {8, 20};

/// The `cap` of search_rows that asks a float network's bilinear block for its canonical frame in double
/// (FramePass::kDouble): LocalSearch::run's second pass over the lanes the float pass left pending.
inline constexpr int kDoubleFramePass = -1;

template <class Real>
using BlockFn = void (*)(const Plan& plan, const Real* raw, const Results<Real>& out, std::size_t first);
/// search_rows (search_kernel.hpp): a block of the given rows, or of rows first.., with an iteration cap.
template <class Real>
using RowsFn = void (*)(const Plan& plan, const Real* raw, const Results<Real>& out, std::size_t first,
                        const std::size_t* rows, int cap);

struct Plan {
  KernelIsa isa = KernelIsa::kBaseline;  ///< the variant every kernel below comes from (isa_dispatch.hpp)
  SurfaceKind kind = SurfaceKind::kBilinear;
  Method method;
  SearchOptions options;
  const NetworkModel* network = nullptr;
  Safeguards guards{};     ///< hybrids: box, step cap, tolerance, halvings
  double inside_lo = 0.0;  ///< ok versus outside: the domain enlarged by domain_margin
  double inside_hi = 0.0;
  int block_size = 8;
  BlockFn<float> block_f = nullptr, single_f = nullptr;
  BlockFn<double> block_d = nullptr, single_d = nullptr;
  /// Newton to convergence, and a float network on bilinear segments: the block kernel with rows and a cap,
  /// for LocalSearch::run's passes.
  RowsFn<float> rows_f = nullptr;
  RowsFn<double> rows_d = nullptr;
  /// A float network on bilinear segments: the block kernels leave the lanes whose canonical frame float does
  /// not decide pending (FramePass::kFloatDeferred), and LocalSearch::run computes them again in blocks of
  /// such lanes with cap kDoubleFramePass.
  bool defer_frame = false;
};

/// The kernels of a plan come from one variant (isa_dispatch.hpp):
/// detail::isa_<name>::select_bilinear_kernels and select_gregory_kernels (kernels_bilinear.cpp,
/// kernels_gregory.cpp) fill plan.block_size and the kernels for plan.kind.

/// For bench_search's breakdown of the network method's time: the first `stage` stages of the network method
/// (1 the rows loaded into a block, 2 + the canonical frame, 3 + the domain test, 4 + the input map, scaling,
/// forward pass and map back) over the whole blocks among `count` queries of `raw` (SPEC 6 rows), with the
/// block width and the code of LocalSearch::run: they run in the kernels' own translation unit (a template
/// instantiated elsewhere could replace them at link time), of the variant a LocalSearch constructed now
/// would take (kernel_isa). `done`: the queries processed. Returns a checksum.
double network_stages(const NetworkModel& model, const double* raw, std::size_t count, int stage,
                      std::size_t& done);

}  // namespace contactnn::search::detail
