// The Gregory instantiations of the block kernels (a file of their own: they take a while to compile).
#include "search/search_kernel.hpp"

namespace contactnn::search::detail {

void select_gregory_kernels(Plan& plan) {
  select_block_kernels<true>(plan);
  select_single_kernels(plan);
}

double network_stages_gregory(const NetworkModel& model, const double* raw, std::size_t count, int stage, std::size_t& done) {
  return network_stages_for<true>(model, raw, count, stage, done);
}

}  // namespace contactnn::search::detail
