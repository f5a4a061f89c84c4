// Replays every input the fuzzers keep (issue 5, part 5): the seed corpus fuzz/corpus/<target>/ and the
// inputs that once crashed or broke a property, fuzz/regressions/<target>/, through the same property checks
// as the libFuzzer targets (fuzz/fuzz_harness.hpp), in the ordinary build, so CI guards every fix.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_harness.hpp"

namespace contactnn::fuzz {
namespace {

std::vector<std::filesystem::path> inputs(const std::string& target) {
  std::vector<std::filesystem::path> files;
  for (const char* folder : {"corpus", "regressions"}) {
    const auto dir = std::filesystem::path(CONTACTNN_SOURCE_DIR) / "fuzz" / folder / target;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.is_regular_file() && entry.path().filename().string()[0] != '.' &&
          entry.path().extension() != ".md") {
        files.push_back(entry.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void replay(const std::string& target, std::string (*check)(const std::uint8_t*, std::size_t)) {
  const auto files = inputs(target);
  ASSERT_FALSE(files.empty()) << "no inputs under fuzz/corpus/" << target;
  for (const auto& file : files) {
    const std::string data = bytes_of(file);
    EXPECT_EQ(check(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()), "") << file;
  }
}

TEST(FuzzRegressions, CsvInputsKeepTheirProperties) { replay("csv", fuzz_csv); }

TEST(FuzzRegressions, ConfigInputsKeepTheirProperties) { replay("config", fuzz_config); }

}  // namespace
}  // namespace contactnn::fuzz
