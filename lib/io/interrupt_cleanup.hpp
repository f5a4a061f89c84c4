// SIGINT / SIGTERM / SIGHUP at any moment leave no temporary file behind: a process-wide registry of the
// temporaries that exist right now, and a signal handler that removes them and exits with 128 + signal.
#pragma once

#include <filesystem>

namespace contactnn::io {

/// Installs the handler for SIGINT, SIGTERM and SIGHUP and ignores SIGPIPE (a write to a closed pipe then
/// fails with EPIPE and is reported as an I/O error, so the temporaries are removed as on any error). On a
/// signal the handler removes every registered temporary (files; directories with the files in them) and
/// ends the process with _exit(128 + signal): 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP.
/// Call it once, from the main thread, before any temporary is registered; the handler always runs on that
/// thread (a signal delivered to another thread is forwarded to it), so registration, creation and commit
/// of temporaries, which happen on the main thread only, never race with the cleanup.
/// Without this call the registry still works but nothing is removed on a signal (library use, tests).
void install_interrupt_cleanup();

/// While alive, `path` is removed by the signal handler (a file by unlink; with `directory`, the files
/// directly inside it and then the directory itself). Register before the file is created and keep the
/// registration until after it has been renamed or removed: removing a path that does not exist is harmless.
/// At most kMaxTemporaries at once, paths of at most kMaxPathBytes - 1 bytes (IoError otherwise).
/// Main thread only.
class TemporaryRegistration {
 public:
  static constexpr int kMaxTemporaries = 32;
  static constexpr std::size_t kMaxPathBytes = 4096;

  explicit TemporaryRegistration(const std::filesystem::path& path, bool directory = false);
  ~TemporaryRegistration();
  TemporaryRegistration(const TemporaryRegistration&) = delete;
  TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;

 private:
  int slot_;
};

/// While alive, a signal is held back: it is recorded, and acted on (cleanup, exit) when the last
/// DeferInterrupts ends. Wraps the few steps that must not be cut in half, such as renaming an output and
/// its effective config one after the other. Main thread only.
class DeferInterrupts {
 public:
  DeferInterrupts();
  ~DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;
};

}  // namespace contactnn::io
