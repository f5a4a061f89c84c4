// The bilinear instantiations of the block kernels (a file of their own: they take a while to compile).
// Compiled once per instruction-set variant (lib/search/CMakeLists.txt), which names the namespace of its
// entry points (CONTACTNN_KERNEL_ISA, e.g. isa_avx2; isa_dispatch.hpp).
#include "search/isa_dispatch.hpp"
#include "search/search_kernel.hpp"

#ifndef CONTACTNN_KERNEL_ISA
#error \
    "kernels_bilinear.cpp is compiled once per variant by lib/search/CMakeLists.txt, which defines CONTACTNN_KERNEL_ISA"
#endif

CONTACTNN_DECLARE_KERNEL_ISA(CONTACTNN_KERNEL_ISA)

namespace contactnn::search::detail::CONTACTNN_KERNEL_ISA {

void select_bilinear_kernels(Plan& plan) {
  select_block_kernels<false>(plan);
  select_single_kernels(plan);
}

double network_stages_bilinear(const NetworkModel& model, const double* raw, std::size_t count, int stage,
                               std::size_t& done) {
  return network_stages_for<false>(model, raw, count, stage, done);
}

}  // namespace contactnn::search::detail::CONTACTNN_KERNEL_ISA
