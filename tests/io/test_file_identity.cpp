// io::same_file and io::require_distinct (issue 12, case 4): an output is the same file as an input whatever
// the spelling (./x, a symbolic link, a hard link), and the refusal names both options.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "io/file_identity.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;

/// A folder of its own for the running test case: ctest -j runs the cases as separate processes at once, and
/// a shared folder, emptied by one case while the other filled it, failed a clean CI-style run.
fs::path fresh_dir() {
  const fs::path dir = testing::test_output_dir("test-file-identity") /
                       ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "data.h5") << "data";
  std::ofstream(dir / "other.h5") << "other";
  fs::create_symlink("data.h5", dir / "link.h5");
  fs::create_hard_link(dir / "data.h5", dir / "sub" / "hard.h5");
  return dir;
}

TEST(FileIdentity, EverySpellingOfAFileIsTheSameFile) {
  const fs::path dir = fresh_dir();
  const fs::path data = dir / "data.h5";
  EXPECT_TRUE(same_file(data, data));
  EXPECT_TRUE(same_file(data, dir / "." / "data.h5"));
  EXPECT_TRUE(same_file(data, dir / "sub" / ".." / "data.h5"));
  EXPECT_TRUE(same_file(data, dir / "link.h5"));
  EXPECT_TRUE(same_file(data, dir / "sub" / "hard.h5"));
  EXPECT_FALSE(same_file(data, dir / "other.h5"));
  EXPECT_FALSE(same_file(data, dir / "absent.h5"));
  // Two outputs that do not exist yet: the same path once dots are resolved.
  EXPECT_TRUE(same_file(dir / "new.h", dir / "sub" / ".." / "new.h"));
  EXPECT_FALSE(same_file(dir / "new.h", dir / "new.h5"));
  // Devices are written in place, never replaced: not "the same file" even as themselves.
  EXPECT_FALSE(same_file("/dev/null", "/dev/null"));
}

TEST(FileIdentity, AnOutputThatIsAnInputIsRefusedNamingBothOptions) {
  const fs::path dir = fresh_dir();
  try {
    require_distinct({{"--output", dir / "link.h5"}}, {{"--data", dir / "data.h5"}, {"--config", ""}});
    FAIL() << "an output that is an input was accepted";
  } catch (const InvalidArgument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--output '" + (dir / "link.h5").string() + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("--data '" + (dir / "data.h5").string() + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("refusing to overwrite an input"), std::string::npos) << m;
  }
  EXPECT_THROW(require_distinct(
                   {{"--output", dir / "new.h5"}, {"--export-header", dir / "sub" / ".." / "new.h5"}}, {}),
               InvalidArgument);
  EXPECT_NO_THROW(require_distinct({{"--output", dir / "new.h5"}, {"--export-header", ""}},
                                   {{"--data", dir / "data.h5"}}));
}

}  // namespace
}  // namespace contactnn::io
