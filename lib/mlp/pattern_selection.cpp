#include "mlp/pattern_selection.hpp"

#include <utility>

#include "core/error.hpp"
#include "mlp/random.hpp"

namespace contactnn::mlp {

PatternSelection select_patterns(const std::vector<std::uint32_t>& candidates, std::size_t training_count,
                                 std::size_t validation_count, std::uint64_t seed) {
  const std::size_t wanted = training_count + validation_count;
  CONTACTNN_REQUIRE(training_count >= 1, "at least one training pattern is needed");
  CONTACTNN_REQUIRE(wanted <= candidates.size(),
                    "cannot select " << training_count << " training and " << validation_count
                                     << " validation patterns from " << candidates.size() << " candidates");
  std::vector<std::uint32_t> pool = candidates;
  Rng rng(seed);
  for (std::size_t i = 0; i < wanted; ++i) {
    const std::size_t j = i + static_cast<std::size_t>(rng.below(pool.size() - i));
    std::swap(pool[i], pool[j]);
  }
  PatternSelection s;
  s.training.assign(pool.begin(), pool.begin() + static_cast<std::ptrdiff_t>(training_count));
  s.validation.assign(pool.begin() + static_cast<std::ptrdiff_t>(training_count),
                      pool.begin() + static_cast<std::ptrdiff_t>(wanted));
  return s;
}

}  // namespace contactnn::mlp
