// The one-lane instantiations of the block kernels, for queries outside whole blocks. This file is compiled
// without auto-vectorisation (see CMakeLists.txt and select_single_kernels in search_kernel.hpp).
#include "search/search_kernel.hpp"

namespace contactnn::search::detail {

void select_single_kernels(Plan& plan) {
  const bool float_network = plan.method.needs_network() && plan.network != nullptr && plan.network->is_float();
  if (plan.kind == SurfaceKind::kGregory) {
    plan.single_f = float_network ? &search_block<true, float, 1, float> : &search_block<true, double, 1, float>;
    plan.single_d = float_network ? &search_block<true, float, 1, double> : &search_block<true, double, 1, double>;
  } else {
    plan.single_f = float_network ? &search_block<false, float, 1, float> : &search_block<false, double, 1, float>;
    plan.single_d = float_network ? &search_block<false, float, 1, double> : &search_block<false, double, 1, double>;
  }
}

}  // namespace contactnn::search::detail
