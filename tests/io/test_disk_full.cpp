// A full disk at every moment of an HDF5 write (issue 12, case 1): write_dataset and write_network throw
// IoError naming the file, leave nothing behind, and the process then exits normally. Before the fix the
// exit itself crashed: HDF5 1.10's atexit handler closed again the file id that the failed H5Fclose had
// half destroyed (SIGSEGV, exit 139).
//
// The full disk is a file-size limit (RLIMIT_FSIZE with SIGXFSZ ignored, so a write past it fails with
// EFBIG as a full disk fails with ENOSPC); it needs no root and no mount. Each limit runs in a forked child
// that ends with exit(), which runs the atexit handlers where the crash was. This is its own executable so
// that no other test initialises HDF5 first (the library must be initialised by contactnn's own code).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <functional>
#include <string>

#include "core/error.hpp"
#include "io/dataset_file.hpp"
#include "io/network_file.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;

constexpr int kWroteWhole = 10;  ///< the child's exit code when the write fitted under the limit
constexpr int kIoError = 11;     ///< ... when it threw IoError naming the file

dataset::LabelledSet labelled_set(Eigen::Index n) {
  dataset::LabelledSet set;
  set.resize(n, SurfaceKind::kBilinear);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int f = 0; f < 8; ++f) set.features(i, f) = 0.001 * static_cast<double>(i * 8 + f);
    set.labels(i, 0) = 0.1;
    set.labels(i, 1) = -0.2;
    set.gap[i] = 0.0;
    set.iterations[i] = 3;
    set.status[static_cast<std::size_t>(i)] = Status::kOk;
    set.scale[i] = 1.0;
  }
  set.config_toml = "[gen-configs]\n";
  return set;
}

/// Runs `write` in a child under a file-size limit of `limit` bytes; the child exits through exit().
int write_under_limit(rlim_t limit, const fs::path& final_path, const std::function<void()>& write) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit r{limit, limit};
    ::setrlimit(RLIMIT_FSIZE, &r);
    int code = kWroteWhole;
    try {
      write();
    } catch (const IoError& e) {
      code = std::string(e.what()).find(final_path.string()) != std::string::npos ? kIoError : 12;
    } catch (...) {
      code = 13;
    }
    std::exit(code);  // atexit handlers run here: HDF5's termination among them
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

/// Sweeps the limit over the whole size of the file `write` makes at `path` when nothing stops it.
void sweep(const fs::path& path, const std::function<void()>& write) {
  write();
  const auto full_size = static_cast<rlim_t>(fs::file_size(path));
  fs::remove(path);
  int failures = 0;
  for (rlim_t limit = 0; limit <= full_size + 4096; limit += std::max<rlim_t>(1, full_size / 97)) {
    const int status = write_under_limit(limit, path, write);
    ASSERT_TRUE(WIFEXITED(status)) << "limit " << limit << " of " << full_size << ": ended by signal "
                                   << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    const int code = WEXITSTATUS(status);
    ASSERT_TRUE(code == kWroteWhole || code == kIoError) << "limit " << limit << ": child exit code " << code;
    if (code == kIoError) {
      ++failures;
      EXPECT_FALSE(fs::exists(path)) << "limit " << limit << ": a failed write left the output";
    }
    for (const auto& e : fs::directory_iterator(path.parent_path())) {
      EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos)
          << "limit " << limit << ": temporary " << e.path() << " left behind";
    }
    if (fs::exists(path)) fs::remove(path);
  }
  EXPECT_GT(failures, 10) << "the limit never made the write fail";
}

TEST(DiskFull, ADatasetWriteFailsCleanlyAtEveryPointAndTheProcessExitsNormally) {
  const fs::path dir = testing::test_output_dir("test-disk-full") / "dataset";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const dataset::LabelledSet set = labelled_set(3000);
  sweep(dir / "data.h5", [&] { write_dataset(dir / "data.h5", set); });
}

TEST(DiskFull, ANetworkOrCheckpointWriteFailsCleanlyAtEveryPoint) {
  const fs::path dir = testing::test_output_dir("test-disk-full") / "network";
  fs::remove_all(dir);
  fs::create_directories(dir);
  geometry::TrainingDomain domain;
  domain.feature_min = std::vector<double>(8, -1.0);
  domain.feature_max = std::vector<double>(8, 1.0);
  mlp::Scaling s;
  s.input_min = domain.feature_min;
  s.input_max = domain.feature_max;
  s.output_min = {-1, -1};
  s.output_max = {1, 1};
  mlp::Network<float> net({8, 64, 32, 2}, 2.0, s);
  net.initialize(1);
  mlp::TrainingState<float> state;
  state.velocity.assign(net.parameter_count(), 0.0f);
  state.best_parameters.assign(net.parameter_count(), 0.0f);
  sweep(dir / "net.h5.checkpoint.h5",
        [&] { write_network(dir / "net.h5.checkpoint.h5", net, domain, {}, &state); });
}

}  // namespace
}  // namespace contactnn::io
