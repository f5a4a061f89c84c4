// Write-then-rename: an interrupted run never leaves a half-written file under the final name.
#pragma once

#include <filesystem>

namespace contactnn::io {

/// Hands out a temporary path in the final file's directory (same file system, so the rename is atomic)
/// and renames it onto the final path on commit(). An uncommitted temporary file is removed by the
/// destructor, so an exception between open and commit leaves nothing behind.
class AtomicOutput {
 public:
  /// @param final_path  where the complete file will appear; its directory must exist (IoError if not).
  explicit AtomicOutput(std::filesystem::path final_path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// `<dir>/.<name>.<pid>.<counter>.tmp`: write the whole output here first.
  [[nodiscard]] const std::filesystem::path& temp_path() const { return temp_path_; }
  [[nodiscard]] const std::filesystem::path& final_path() const { return final_path_; }

  /// Flushes the temporary file to disk and renames it onto the final path. IoError on failure.
  void commit();

 private:
  std::filesystem::path final_path_;
  std::filesystem::path temp_path_;
  bool committed_ = false;
};

}  // namespace contactnn::io
