// Which patterns train and which validate: the paper's "1000 patterns are randomly selected for training".
#pragma once

#include <cstdint>
#include <vector>

namespace contactnn::mlp {

struct PatternSelection {
  std::vector<std::uint32_t> training;    ///< row indices, in draw order
  std::vector<std::uint32_t> validation;  ///< row indices, disjoint from training
};

/// Draws training_count + validation_count distinct rows from `candidates` (e.g. the rows with status ok),
/// uniformly without replacement (partial Fisher-Yates with Rng(seed)); the first training_count drawn
/// train. Same candidates and seed: same selection. Throws InvalidArgument when there are too few.
[[nodiscard]] PatternSelection select_patterns(const std::vector<std::uint32_t>& candidates,
                                               std::size_t training_count, std::size_t validation_count,
                                               std::uint64_t seed);

}  // namespace contactnn::mlp
