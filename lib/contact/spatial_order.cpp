// The Morton order of the slave nodes (surface_search.hpp, spatial_order): the searches take their nodes in
// it so that consecutive queries meet the same faces and tree nodes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "contact/surface_search.hpp"
#include "core/error.hpp"

namespace contactnn::contact {

namespace {

/// x's low 10 bits spread to every third bit (bits 0, 3, 6, ...).
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x3ff;
  x = (x | (x << 16)) & 0x030000ff;
  x = (x | (x << 8)) & 0x0300f00f;
  x = (x | (x << 4)) & 0x030c30c3;
  x = (x | (x << 2)) & 0x09249249;
  return x;
}

}  // namespace

void spatial_order(std::span<const Vec3> points, std::vector<std::uint32_t>& order,
                   std::vector<std::uint64_t>& scratch, PointBox* box) {
  const std::size_t n = points.size();
  CONTACTNN_REQUIRE(n < (std::size_t{1} << 32), n << " points: at most 2^32 - 1");
  order.resize(n);
  // The points' box and the summed distance between consecutive points, estimated from every fourth step
  // (threads for many points: the order serves the caches, and the answers do not depend on it).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo0 = kInf, lo1 = kInf, lo2 = kInf, hi0 = -kInf, hi1 = -kInf, hi2 = -kInf;
  double step = 0.0;
  const auto total = static_cast<long>(n);
#pragma omp parallel for schedule(static) reduction(min : lo0, lo1, lo2) reduction(max : hi0, hi1, hi2) \
    reduction(+ : step) if (total >= 65536)
  for (long k = 0; k < total; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Vec3& x = points[i];
    if (!x.allFinite()) continue;
    lo0 = std::min(lo0, x[0]);
    lo1 = std::min(lo1, x[1]);
    lo2 = std::min(lo2, x[2]);
    hi0 = std::max(hi0, x[0]);
    hi1 = std::max(hi1, x[1]);
    hi2 = std::max(hi2, x[2]);
    if ((i & 3) == 0 && i > 0 && points[i - 1].allFinite()) step += (x - points[i - 1]).norm();
  }
  step *= 4.0;
  const Vec3 lo(lo0, lo1, lo2), hi(hi0, hi1, hi2);
  if (box != nullptr) *box = PointBox{lo, hi};
  // A mesh's own order (rows of a grid, an element's nodes together) steps a node spacing or two on average,
  // about extent / sqrt(n) on a surface; kept, it is at least as local as the Z curve. Only an order that
  // steps farther (a random one) is sorted.
  const double largest = (hi - lo).maxCoeff();
  if (n < 2 || !std::isfinite(largest) || !(step <= largest * static_cast<double>(n)) ||
      step < 8.0 * largest * std::sqrt(static_cast<double>(n))) {
#pragma omp parallel for schedule(static) if (total >= 65536)
    for (long k = 0; k < total; ++k) order[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(k);
    return;
  }
  // Each key: the 30-bit Morton code above the point's index (32 bits).
  scratch.resize(2 * n);
  std::uint64_t* keys = scratch.data();
  std::uint64_t* other = scratch.data() + n;
  // Cubic cells, the largest extent's 1/1024: a thin direction (a sheet's thickness) takes few cells and the
  // low bits, where a cell count of its own would let its jitter scatter neighbours along the sheet.
  const double extent = (hi - lo).maxCoeff();
#pragma omp parallel for schedule(static) if (total >= 65536)
  for (long k = 0; k < total; ++k) {
    const auto i = static_cast<std::size_t>(k);
    std::uint64_t code = 0;
    if (points[i].allFinite()) {
      for (int d = 0; d < 3; ++d) {
        const double t = extent > 0.0 ? (points[i][d] - lo[d]) / extent : 0.0;
        const auto cell = static_cast<std::uint64_t>(std::clamp(t * 1024.0, 0.0, 1023.0));
        code |= spread_bits(cell) << d;
      }
    }
    keys[i] = (code << 32) | i;
  }
  // Two passes of 15 bits over the code (a stable LSD radix sort).
  constexpr int kBits = 15;
  std::vector<std::uint32_t> count(std::size_t{1} << kBits);
  for (int pass = 0; pass < 2; ++pass) {
    const int shift = 32 + pass * kBits;
    std::fill(count.begin(), count.end(), 0U);
    for (std::size_t i = 0; i < n; ++i) ++count[(keys[i] >> shift) & ((1U << kBits) - 1)];
    std::uint32_t sum = 0;
    for (std::uint32_t& c : count) {
      const std::uint32_t here = c;
      c = sum;
      sum += here;
    }
    for (std::size_t i = 0; i < n; ++i) other[count[(keys[i] >> shift) & ((1U << kBits) - 1)]++] = keys[i];
    std::swap(keys, other);
  }
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(keys[i] & 0xffffffffU);
}

}  // namespace contactnn::contact
