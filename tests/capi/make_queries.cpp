// capi_make_queries: a RAW.csv (SPEC 6) of random local-search queries for the consumer tests
// (consumer_check.py): configurations of the paper's domain of the surface, placed at a random position,
// orientation, scale and node order (search/random_queries.hpp), with every seventh row made hostile
// (a non-finite value, a collapsed segment, a far slave node, a tiny or huge scale, a random box). Every
// value is rounded to float, so that a float run of the C interface sees exactly the double run's input.
//
// Usage: capi_make_queries bilinear|gregory COUNT SEED OUTPUT.csv
#include <cstdio>
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

  // Rows from the fourth on spoiled; tiny and huge within float's range (the float run must see the same
  // values).
  testing::Spoiling spoiling;
  spoiling.first = 3;
  spoiling.tiny = 1e-20;
  spoiling.huge = 1e20;
  const std::vector<double> raw = testing::mixed_queries(kind, count, seed, spoiling);

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
