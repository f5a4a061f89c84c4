// libFuzzer target: config file text through cli::parse_config_text (the [section] reader, CLI11's TOML
// parser, value checks). Properties: fuzz_harness.hpp. Built and run by scripts/fuzz.
#include <cstdio>
#include <cstdlib>

#include "fuzz_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = contactnn::fuzz::fuzz_config(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_config: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
