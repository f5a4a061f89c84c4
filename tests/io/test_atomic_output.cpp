// io::AtomicOutput, commit_together, require_writable and AtomicDirectory (issue 12): what the final path
// names decides between rename and writing in place, nothing is left behind on failure, and a directory is
// replaced whole or not at all.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <future>
#include <iterator>
#include <string>

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/csv.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;

/// A fresh, empty directory for one test.
fs::path fresh_dir(const std::string& name) { return testing::fresh_test_dir("test-atomic-output", name); }

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

/// Every entry of `dir`, names only, sorted.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(AtomicOutput, ARegularFileIsReplacedByRenameKeepingItsPermissions) {
  const fs::path dir = fresh_dir("regular");
  const fs::path out = dir / "out.csv";
  write_text(out, "old\n");
  ::chmod(out.c_str(), 0640);
  struct stat before {};
  ::stat(out.c_str(), &before);
  write_text_atomically(out, "new\n");
  struct stat after {};
  ::stat(out.c_str(), &after);
  EXPECT_EQ(read_text(out), "new\n");
  EXPECT_NE(after.st_ino, before.st_ino) << "expected a new file renamed into place";
  EXPECT_EQ(after.st_mode & 07777, 0640u);
  EXPECT_EQ(entries(dir), std::vector<std::string>{"out.csv"});
}

TEST(AtomicOutput, AnUncommittedOutputLeavesNothingAndKeepsTheOldFile) {
  const fs::path dir = fresh_dir("uncommitted");
  write_text(dir / "out.csv", "old\n");
  {
    AtomicOutput output(dir / "out.csv");
    write_text(output.write_path(), "half");
    EXPECT_EQ(output.write_path().parent_path(), dir);
  }
  EXPECT_EQ(read_text(dir / "out.csv"), "old\n");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"out.csv"});
}

TEST(AtomicOutput, ASymlinkToARegularFileIsKeptAndItsTargetReplaced) {
  const fs::path dir = fresh_dir("symlink");
  fs::create_directories(dir / "real");
  write_text(dir / "real" / "target.csv", "old\n");
  fs::create_symlink("real/target.csv", dir / "link.csv");
  write_text_atomically(dir / "link.csv", "new\n");
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(read_text(dir / "real" / "target.csv"), "new\n");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"link.csv", "real"}));
  EXPECT_EQ(entries(dir / "real"), std::vector<std::string>{"target.csv"});
}

TEST(AtomicOutput, ADanglingSymlinkCreatesItsTarget) {
  const fs::path dir = fresh_dir("dangling");
  fs::create_symlink("made.csv", dir / "link.csv");
  write_text_atomically(dir / "link.csv", "x\n");
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(read_text(dir / "made.csv"), "x\n");
}

TEST(AtomicOutput, DevNullIsWrittenInPlaceNeverReplaced) {
  // Seekable (HDF5: a temporary in $TMPDIR, then copied) and sequential (straight into the device).
  for (const auto access : {AtomicOutput::Access::kSeekable, AtomicOutput::Access::kSequential}) {
    AtomicOutput output("/dev/null", access);
    EXPECT_TRUE(output.in_place());
    write_text(output.write_path(), "discarded");
    output.commit();
    struct stat st {};
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null was replaced";
  }
  const fs::path dir = fresh_dir("link-to-null");
  fs::create_symlink("/dev/null", dir / "null.csv");
  write_text_atomically(dir / "null.csv", "discarded\n");
  EXPECT_TRUE(fs::is_symlink(dir / "null.csv"));
  EXPECT_TRUE(written_in_place(dir / "null.csv"));
}

TEST(AtomicOutput, AFifoIsWrittenInPlaceForBothAccessKinds) {
  const fs::path dir = fresh_dir("fifo");
  const fs::path fifo = dir / "out.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const auto access : {AtomicOutput::Access::kSeekable, AtomicOutput::Access::kSequential}) {
    auto reader = std::async(std::launch::async, [&] { return read_text(fifo); });
    {
      AtomicOutput output(fifo, access);
      EXPECT_TRUE(output.in_place());
      write_text(output.write_path(), "through the pipe\n");
      output.commit();
    }
    EXPECT_EQ(reader.get(), "through the pipe\n");
    struct stat st {};
    ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced";
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"out.fifo"});
}

TEST(AtomicOutput, ADirectoryOrAMissingDirectoryIsAnIoError) {
  const fs::path dir = fresh_dir("errors");
  fs::create_directories(dir / "sub");
  try {
    AtomicOutput output(dir / "sub");
    FAIL() << "a directory was accepted as an output";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
  EXPECT_THROW(AtomicOutput(dir / "missing" / "out.csv"), IoError);
  EXPECT_THROW(require_writable(dir / "missing" / "out.csv"), IoError);
  EXPECT_THROW(require_writable(dir / "sub"), IoError);
  EXPECT_NO_THROW(require_writable(dir / "fine.csv"));
  EXPECT_EQ(entries(dir), std::vector<std::string>{"sub"}) << "require_writable left its probe behind";
}

TEST(AtomicOutput, CommitTogetherPutsEveryOutputInPlace) {
  const fs::path dir = fresh_dir("together");
  auto a = write_text_uncommitted(dir / "a.h5", "A");
  auto b = write_text_uncommitted(dir / "a.h5.config.toml", "B");
  EXPECT_TRUE(entries(dir).size() == 2 && !fs::exists(dir / "a.h5") && !fs::exists(dir / "a.h5.config.toml"));
  commit_together({a.get(), nullptr, b.get()});
  EXPECT_EQ(read_text(dir / "a.h5"), "A");
  EXPECT_EQ(read_text(dir / "a.h5.config.toml"), "B");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"a.h5", "a.h5.config.toml"}));
}

TEST(AtomicDirectory, ReplacesAReportWholeAndLeavesNoTemporary) {
  const fs::path parent = fresh_dir("directory");
  const fs::path report = parent / "report";
  fs::create_directories(report);
  write_text(report / "errors.csv", "old errors\n");
  write_text(report / "speed.csv", "old speed\n");
  {
    AtomicDirectory d(report, {"errors.csv", "speed.csv", "report.md"}, "--report");
    write_text(d.write_path() / "errors.csv", "new errors\n");
    write_text(d.write_path() / "report.md", "new report\n");
    // Until the commit, the previous report is whole.
    EXPECT_EQ(read_text(report / "errors.csv"), "old errors\n");
    d.commit();
  }
  EXPECT_EQ(entries(report), (std::vector<std::string>{"errors.csv", "report.md"}));
  EXPECT_EQ(read_text(report / "errors.csv"), "new errors\n");
  EXPECT_EQ(entries(parent), std::vector<std::string>{"report"});
}

TEST(AtomicDirectory, AnUncommittedReportLeavesThePreviousOneAsItWas) {
  const fs::path parent = fresh_dir("directory-failed");
  fs::create_directories(parent / "report");
  write_text(parent / "report" / "errors.csv", "old\n");
  {
    AtomicDirectory d(parent / "report", {"errors.csv"}, "--report");
    write_text(d.write_path() / "errors.csv", "half");
  }
  EXPECT_EQ(read_text(parent / "report" / "errors.csv"), "old\n");
  EXPECT_EQ(entries(parent), std::vector<std::string>{"report"});
}

TEST(AtomicDirectory, ADirectoryHoldingOtherFilesIsNeverReplaced) {
  const fs::path parent = fresh_dir("directory-foreign");
  fs::create_directories(parent / "home");
  write_text(parent / "home" / "thesis.tex", "precious\n");
  try {
    AtomicDirectory d(parent / "home", {"errors.csv"}, "--report");
    FAIL() << "a directory with a foreign file was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("'thesis.tex'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--report"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(parent / "home" / "thesis.tex"), "precious\n");
  EXPECT_EQ(entries(parent), std::vector<std::string>{"home"});
}

TEST(AtomicDirectory, ANewDirectoryIsCreatedWithItsParents) {
  const fs::path parent = fresh_dir("directory-new");
  AtomicDirectory d(parent / "a" / "b", {"x"}, "--report");
  write_text(d.write_path() / "x", "1");
  d.commit();
  EXPECT_EQ(read_text(parent / "a" / "b" / "x"), "1");
  EXPECT_EQ(entries(parent / "a"), std::vector<std::string>{"b"});
}

}  // namespace
}  // namespace contactnn::io
