// FaceSearch's block kernels (face_search_kernel.hpp), compiled once per instruction-set variant
// (lib/search/CMakeLists.txt, isa_dispatch.hpp), which names the namespace of the entry point.
#include "search/face_search_kernel.hpp"

#ifndef CONTACTNN_KERNEL_ISA
#error \
    "face_kernels.cpp is compiled once per variant by lib/search/CMakeLists.txt, which defines CONTACTNN_KERNEL_ISA"
#endif

CONTACTNN_DECLARE_KERNEL_ISA(CONTACTNN_KERNEL_ISA)

namespace contactnn::search::detail {
namespace {

template <int kFace>
void select(FacePlan& plan) {
  // 16 lanes for every method with Newton steps (measured with bench_search on AVX-512: at 32 lanes a tri6
  // newton:5 took 53 ns a query against 19 at 16, its lane loops spilling the face's coefficients), 32 for
  // the closed form and a network alone (tri6 closed form 8.8 ns against 11.2 at 16).
  const bool narrow = plan.method.to_convergence || plan.method.newton_steps > 0;
  if (narrow) {
    plan.block_size = 16;
    plan.block_f = &face_block<kFace, 16, float>;
    plan.block_d = &face_block<kFace, 16, double>;
  } else {
    plan.block_size = 32;
    plan.block_f = &face_block<kFace, 32, float>;
    plan.block_d = &face_block<kFace, 32, double>;
  }
  select_face_single_kernels(plan);
}

}  // namespace
}  // namespace contactnn::search::detail

namespace contactnn::search::detail::CONTACTNN_KERNEL_ISA {

void select_face_kernels(FacePlan& plan) {
  switch (plan.kind) {
    case FaceKind::kTri3: select<0>(plan); break;
    case FaceKind::kTri6: select<1>(plan); break;
    case FaceKind::kQuad8: select<2>(plan); break;
  }
}

}  // namespace contactnn::search::detail::CONTACTNN_KERNEL_ISA
