// libFuzzer target: config file text through cli::parse_config_text (the [section] reader, CLI11's TOML
// parser, value checks). Properties: fuzz_harness.hpp. Built and run by scripts/fuzz.
#include "fuzz_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return contactnn::fuzz::verdict("fuzz_config", contactnn::fuzz::fuzz_config(data, size));
}
