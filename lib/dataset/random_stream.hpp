// Counter-based random numbers for datasets: configuration i draws from its own stream (seed, i), so a
// dataset is the same for any thread count and row order of the work.
#pragma once

#include <array>
#include <cstdint>

#include "geometry/surface_point.hpp"

namespace contactnn::dataset {

/// splitmix64 (Steele, Lea & Flood 2014) over the state seed * FNV prime + index.
class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t index) : state_(seed * 0x100000001B3ULL + index) {}
  /// Next 64 random bits.
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1), 53 random bits.
  double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

 private:
  std::uint64_t state_;
};

/// Node normals for a segment (nodes counter-clockwise): each corner's own unit normal
/// (next - X) x (prev - X), tilted in a uniformly random direction by an angle whose tangent is uniform in
/// [0, max_tangent) (the paper's Section 6.3.1: "the tangent of the angle ... is below 0.2"). Unit length.
[[nodiscard]] std::array<geometry::Vec3, 4> random_node_normals(const std::array<geometry::Vec3, 4>& nodes,
                                                                double max_tangent, RandomStream& random);

}  // namespace contactnn::dataset
