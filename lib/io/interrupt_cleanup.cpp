#include "io/interrupt_cleanup.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

#include "core/error.hpp"

// Why a handler that unlinks and exits, rather than a flag checked at safe points: the long stretches of
// work (an OpenMP labelling loop, an epoch, an HDF5 write, a blocking open of a FIFO) have no safe point
// to check from, and a user who presses Ctrl-C expects the tool to stop now, not after the next chunk.
// unlink, rmdir, open, getdents64, close, tgkill and _exit are all plain system calls, safe in a handler;
// the registry is a fixed array of atomics and char buffers, so the handler takes no lock and allocates
// nothing. Everything that creates, renames or unregisters a temporary runs on the main thread, and the
// handler runs only there (forwarding from other threads), so the handler can never see a half-made
// registration: a slot is published only once its path is complete, before the file is created.

namespace contactnn::io {

namespace {

enum SlotState : int { kFree = 0, kFilling = 1, kLiveFile = 2, kLiveDirectory = 3 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[TemporaryRegistration::kMaxPathBytes];
};

Slot g_slots[TemporaryRegistration::kMaxTemporaries];
std::atomic<int> g_defer_depth{0};
std::atomic<int> g_pending_signal{0};
std::atomic<pid_t> g_main_thread{0};

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

/// Removes the entries of a flat directory (a report being written) and the directory. Entries removed while
/// reading may shift the listing, so it is read again from the start until only "." and ".." remain.
void remove_directory(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) static char buffer[8192];
    for (int pass = 0; pass < 16; ++pass) {
      bool removed = false;
      ::lseek(fd, 0, SEEK_SET);
      for (;;) {
        const ssize_t n = ::getdents64(fd, buffer, sizeof buffer);
        if (n <= 0) break;
        for (ssize_t offset = 0; offset < n;) {
          const auto* entry = reinterpret_cast<const struct dirent64*>(buffer + offset);
          offset += entry->d_reclen;
          const char* name = entry->d_name;
          if (name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))) continue;
          if (::unlinkat(fd, name, 0) == 0) removed = true;
        }
      }
      if (!removed) break;
    }
    ::close(fd);
  }
  ::rmdir(path);
}

[[noreturn]] void clean_up_and_exit(int signal_number) {
  for (Slot& slot : g_slots) {
    const int state = slot.state.load();
    if (state == kLiveFile) ::unlink(slot.path);
    if (state == kLiveDirectory) remove_directory(slot.path);
  }
  ::_exit(128 + signal_number);
}

void on_signal(int signal_number) {
  const int saved_errno = errno;
  const pid_t main_thread = g_main_thread.load();
  if (main_thread != 0 && ::gettid() != main_thread) {
    // Only the main thread creates and renames temporaries: let it do the cleanup, between two of its steps.
    ::tgkill(::getpid(), main_thread, signal_number);
    errno = saved_errno;
    return;
  }
  g_pending_signal.store(signal_number);
  if (g_defer_depth.load() > 0) {
    errno = saved_errno;
    return;
  }
  clean_up_and_exit(signal_number);
}

}  // namespace

void install_interrupt_cleanup() {
  g_main_thread.store(::gettid());
  struct sigaction action {};
  action.sa_handler = on_signal;
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);
  for (const int s : kSignals) sigaddset(&action.sa_mask, s);
  for (const int s : kSignals) ::sigaction(s, &action, nullptr);
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  ::sigaction(SIGPIPE, &ignore, nullptr);
}

TemporaryRegistration::TemporaryRegistration(const std::filesystem::path& path, bool directory) : slot_(-1) {
  const std::string& text = path.native();
  CONTACTNN_REQUIRE_AS(IoError, text.size() < kMaxPathBytes,
                       "path of " << text.size() << " bytes is too long for a temporary file (at most "
                                  << kMaxPathBytes - 1 << ")");
  for (int i = 0; i < kMaxTemporaries; ++i) {
    int expected = kFree;
    if (g_slots[i].state.compare_exchange_strong(expected, kFilling)) {
      std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
      g_slots[i].state.store(directory ? kLiveDirectory : kLiveFile);
      slot_ = i;
      return;
    }
  }
  throw IoError("more than " + std::to_string(kMaxTemporaries) + " temporary files at once (a bug)");
}

TemporaryRegistration::~TemporaryRegistration() {
  if (slot_ >= 0) g_slots[slot_].state.store(kFree);
}

DeferInterrupts::DeferInterrupts() { g_defer_depth.fetch_add(1); }

DeferInterrupts::~DeferInterrupts() {
  if (g_defer_depth.fetch_sub(1) == 1) {
    const int pending = g_pending_signal.load();
    if (pending != 0) clean_up_and_exit(pending);
  }
}

}  // namespace contactnn::io
