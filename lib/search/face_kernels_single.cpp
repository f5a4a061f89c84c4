// FaceSearch's one-lane kernels, compiled without auto-vectorisation (lib/search/CMakeLists.txt), once per
// instruction-set variant: a query alone rounds as a lane of a block (see kernels_single.cpp).
#include "search/face_search_kernel.hpp"

namespace contactnn::search::detail {

void select_face_single_kernels(FacePlan& plan) {
  switch (plan.kind) {
    case FaceKind::kTri3:
      plan.single_f = &face_block<0, 1, float>;
      plan.single_d = &face_block<0, 1, double>;
      break;
    case FaceKind::kTri6:
      plan.single_f = &face_block<1, 1, float>;
      plan.single_d = &face_block<1, 1, double>;
      break;
    case FaceKind::kQuad8:
      plan.single_f = &face_block<2, 1, float>;
      plan.single_d = &face_block<2, 1, double>;
      break;
  }
}

}  // namespace contactnn::search::detail
