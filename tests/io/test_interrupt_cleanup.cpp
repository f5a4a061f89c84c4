// io::install_interrupt_cleanup (issue 12): a signal removes every registered temporary and ends the process
// with 128 + signal; DeferInterrupts holds it back until a group of renames is done. Each case runs in a
// forked child, the one place a test may take a signal and exit.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <functional>
#include <thread>

#include "io/atomic_output.hpp"
#include "io/csv.hpp"
#include "io/interrupt_cleanup.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  return testing::fresh_test_dir("test-interrupt-cleanup", name);
}

void touch(const fs::path& path) { std::ofstream(path) << "x"; }

/// Runs `child` in a forked process, after install_interrupt_cleanup() there, and returns its wait status.
/// The child ends with _exit(0) if `child` returns (it should have been ended by a signal before), _exit(99)
/// if it throws.
int in_child(const std::function<void()>& child) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    try {
      install_interrupt_cleanup();
      child();
    } catch (...) {
      ::_exit(99);
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST(InterruptCleanup, SigtermRemovesRegisteredFilesAndDirectoriesAndExits143) {
  const fs::path dir = fresh_dir("sigterm");
  const int status = in_child([&] {
    const TemporaryRegistration file(dir / ".out.csv.1.0.tmp");
    touch(dir / ".out.csv.1.0.tmp");
    const TemporaryRegistration directory(dir / ".report.1.1.tmp", true);
    fs::create_directories(dir / ".report.1.1.tmp");
    touch(dir / ".report.1.1.tmp" / "errors.csv");
    touch(dir / ".report.1.1.tmp" / "report.md");
    touch(dir / "kept.csv");  // not registered: a committed output
    ::raise(SIGTERM);
    for (;;) ::pause();
  });
  ASSERT_TRUE(WIFEXITED(status)) << "ended by a signal instead of exiting";
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_FALSE(fs::exists(dir / ".out.csv.1.0.tmp"));
  EXPECT_FALSE(fs::exists(dir / ".report.1.1.tmp"));
  EXPECT_TRUE(fs::exists(dir / "kept.csv"));
}

TEST(InterruptCleanup, SigintDuringAnAtomicOutputLeavesNoTemporaryAndExits130) {
  const fs::path dir = fresh_dir("sigint");
  const int status = in_child([&] {
    AtomicOutput output(dir / "out.csv");
    touch(output.write_path());
    ::raise(SIGINT);
    for (;;) ::pause();
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(InterruptCleanup, ASignalInsideDeferInterruptsActsAfterTheCommits) {
  const fs::path dir = fresh_dir("deferred");
  const int status = in_child([&] {
    auto a = write_text_uncommitted(dir / "a.h5", "A");
    auto b = write_text_uncommitted(dir / "a.h5.config.toml", "B");
    {
      const DeferInterrupts defer;
      ::raise(SIGTERM);  // held back: the pair is committed whole
      commit_together({a.get(), b.get()});
    }
    for (;;) ::pause();  // not reached: the held-back signal ends the process when `defer` ends
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_TRUE(fs::exists(dir / "a.h5"));
  EXPECT_TRUE(fs::exists(dir / "a.h5.config.toml"));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names.size(), 2u) << "a temporary was left behind";
}

TEST(InterruptCleanup, ASignalToAnotherThreadIsHandledOnTheMainThread) {
  const fs::path dir = fresh_dir("other-thread");
  const int status = in_child([&] {
    const TemporaryRegistration file(dir / ".x.tmp");
    touch(dir / ".x.tmp");
    std::thread worker([] {
      ::raise(SIGTERM);  // raise() sends to the calling thread
      for (;;) ::pause();
    });
    worker.detach();
    for (;;) ::pause();
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  EXPECT_FALSE(fs::exists(dir / ".x.tmp"));
}

}  // namespace
}  // namespace contactnn::io
