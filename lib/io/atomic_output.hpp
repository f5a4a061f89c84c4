// Write-then-rename: an interrupted or failed run never leaves a half-written file under the final name,
// and never replaces what is not a regular file.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>

#include "io/interrupt_cleanup.hpp"

namespace contactnn::io {

/// One output file, written completely before it appears under its final name.
///
/// What the final path names decides how:
///  - nothing, or a regular file: the output is written to a temporary `<dir>/.<name>.<pid>.<n>.tmp` in the
///    same directory (same file system, so the rename is atomic), flushed to disk and renamed onto the final
///    name by commit(); a replaced file keeps its permission bits.
///  - a symbolic link (to any depth): followed; the rules apply to its final target, so a link to a regular
///    file is kept and its target is replaced atomically, a link to /dev/null writes to /dev/null.
///  - something that is not a regular file (a character device such as /dev/null or /dev/stdout, a FIFO, a
///    socket): never replaced. A sequential output (CSV text) is written straight into it; a seekable one
///    (HDF5) is written to a temporary in the system's temporary directory ($TMPDIR, else /tmp) and copied
///    into it by commit().
///  - a directory: IoError at construction.
/// The temporary is registered for removal on SIGINT/SIGTERM/SIGHUP (interrupt_cleanup.hpp) and removed by
/// the destructor unless committed, so an exception or a signal between construction and commit leaves
/// nothing behind. IoError (naming the path) when the directory does not exist or a step fails; a full disk
/// surfaces as IoError when the data is written, flushed or copied.
class AtomicOutput {
 public:
  enum class Access {
    kSeekable,    ///< the writer needs a seekable regular file (HDF5)
    kSequential,  ///< the writer only appends (CSV, text): a FIFO or device can take it directly
  };

  /// @param final_path  where the complete file will appear.
  explicit AtomicOutput(std::filesystem::path final_path, Access access = Access::kSeekable);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// Where to write the whole output: a temporary, or the target itself (sequential output into a device
  /// or FIFO). Open it with truncation.
  [[nodiscard]] const std::filesystem::path& write_path() const { return write_path_; }
  /// The path as given.
  [[nodiscard]] const std::filesystem::path& final_path() const { return final_path_; }
  /// True when the target exists and is not a regular file (written in place, never replaced).
  [[nodiscard]] bool in_place() const { return in_place_; }

  /// Makes the output appear under its final name (see the class comment). IoError on failure; the
  /// temporary is then removed by the destructor. Signals are held back while it runs.
  void commit();

 private:
  void commit_unguarded();

  std::filesystem::path final_path_;
  std::filesystem::path target_;  // final_path_ with symbolic links followed
  std::filesystem::path write_path_;
  bool in_place_ = false;
  bool has_temporary_ = false;
  bool committed_ = false;
  std::unique_ptr<TemporaryRegistration> registration_;

  friend void commit_together(std::initializer_list<AtomicOutput*> outputs);
};

/// Commits several outputs of one run as a unit (a dataset and its effective config): signals are held
/// back and an exclusive lock (flock) is held on each output's directory while they are renamed, so two
/// runs writing the same outputs at once leave a matching pair from one of them, never a mix. Outputs are
/// committed in the order given. A null pointer is skipped.
void commit_together(std::initializer_list<AtomicOutput*> outputs);

/// True when `path` names an existing non-regular file (device, FIFO; through links too), which outputs are
/// written into in place; false for a regular file, nothing, or a path that cannot be checked.
[[nodiscard]] bool written_in_place(const std::filesystem::path& path);

/// Checks before any work that `path` can be written as an output: its directory exists and a file can be
/// created in it (a probe temporary is created and removed), and it is not a directory. IoError naming the
/// path, the directory and the system's reason otherwise. For outputs written in place (devices, FIFOs)
/// nothing is created.
void require_writable(const std::filesystem::path& path);

/// A directory of outputs (a report) built under a temporary name beside the final one and put in place
/// whole by commit(): an interrupted or failed run leaves the previous directory as it was. An existing
/// directory is replaced only if every entry in it is a name from `owned_names` (files an earlier run of the
/// same tool wrote); otherwise the constructor throws InvalidArgument naming the first foreign entry, so a
/// mistyped --report can never delete a user's files. A symbolic link to a directory is followed.
class AtomicDirectory {
 public:
  AtomicDirectory(std::filesystem::path final_path, std::initializer_list<std::string> owned_names,
                  const std::string& option_name);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  /// The temporary directory to write the files into (created by the constructor).
  [[nodiscard]] const std::filesystem::path& write_path() const { return write_path_; }
  [[nodiscard]] const std::filesystem::path& final_path() const { return final_path_; }

  /// Exchanges the temporary directory with the final one atomically (renameat2 RENAME_EXCHANGE; where the
  /// file system lacks it, two renames) and removes the previous directory. Signals are held back meanwhile.
  void commit();

 private:
  std::filesystem::path final_path_;
  std::filesystem::path target_;
  std::filesystem::path write_path_;
  bool committed_ = false;
  std::unique_ptr<TemporaryRegistration> registration_;
};

}  // namespace contactnn::io
