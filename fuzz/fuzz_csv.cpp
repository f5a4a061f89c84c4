// libFuzzer target: CSV text through io::parse_csv, io::parse_raw_configurations and the labeller.
// Properties: fuzz_harness.hpp. Built and run by scripts/fuzz.
#include <cstdio>
#include <cstdlib>

#include "fuzz_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = contactnn::fuzz::fuzz_csv(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_csv: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
