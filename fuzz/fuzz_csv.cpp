// libFuzzer target: CSV text through io::parse_csv, io::parse_raw_configurations and the labeller.
// Properties: fuzz_harness.hpp. Built and run by scripts/fuzz.
#include "fuzz_harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return contactnn::fuzz::verdict("fuzz_csv", contactnn::fuzz::fuzz_csv(data, size));
}
