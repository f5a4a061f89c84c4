// capi_make_queries: a RAW.csv (SPEC 6) of random local-search queries for the consumer tests
// (consumer_check.py): configurations of the paper's domain of the surface, placed at a random position,
// orientation, scale and node order (search/random_queries.hpp), with every seventh row made hostile
// (a non-finite value, a collapsed segment, a far slave node, a tiny or huge scale, a random box). Every
// value is rounded to float, so that a float run of the C interface sees exactly the double run's input.
//
// Usage: capi_make_queries bilinear|gregory COUNT SEED OUTPUT.csv
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "search/random_queries.hpp"

int main(int argc, char** argv) {
  using namespace contactnn;
  if (argc != 5) {
    std::fprintf(stderr, "usage: capi_make_queries bilinear|gregory COUNT SEED OUTPUT.csv\n");
    return 2;
  }
  const SurfaceKind kind = surface_from_string(argv[1]);
  const std::size_t count = std::stoul(argv[2]);
  const std::uint64_t seed = std::stoull(argv[3]);
  const std::size_t columns = kind == SurfaceKind::kGregory ? 27 : 15;

  std::vector<double> raw = testing::random_queries(kind, count, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 3; i < count; i += 7) {
    double* q = raw.data() + i * columns;
    switch ((i / 7) % 6) {
      case 0:
        q[i % columns] = std::numeric_limits<double>::quiet_NaN();
        break;
      case 1:
        for (int k = 3; k < 6; ++k) q[k] = q[k - 3];
        break;  // A = B
      case 2:
        for (int k = 12; k < 15; ++k) q[k] += 1e3 * u(rng);
        break;
      case 3:
        for (std::size_t k = 0; k < 15; ++k) q[k] *= 1e-20;
        break;
      case 4:
        for (std::size_t k = 0; k < 15; ++k) q[k] *= 1e20;
        break;
      default:
        for (std::size_t k = 0; k < columns; ++k) q[k] = 1e3 * u(rng);
        break;
    }
  }

  std::FILE* out = std::fopen(argv[4], "w");
  if (out == nullptr) {
    std::fprintf(stderr, "capi_make_queries: cannot write %s\n", argv[4]);
    return 1;
  }
  std::fprintf(out, "id");
  for (const auto name : kRawPointColumns)
    std::fprintf(out, ",%.*s", static_cast<int>(name.size()), name.data());
  if (kind == SurfaceKind::kGregory) {
    for (const auto name : kRawNormalColumns)
      std::fprintf(out, ",%.*s", static_cast<int>(name.size()), name.data());
  }
  std::fprintf(out, "\n");
  for (std::size_t i = 0; i < count; ++i) {
    std::fprintf(out, "%zu", i + 1);
    for (std::size_t k = 0; k < columns; ++k) {
      std::fprintf(out, ",%.17g", static_cast<double>(static_cast<float>(raw[i * columns + k])));
    }
    std::fprintf(out, "\n");
  }
  return std::fclose(out) == 0 ? 0 : 1;
}
