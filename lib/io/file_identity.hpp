// Outputs are compared with inputs by what they are (device and inode), not by how they are spelled, so
// that `--output ./x`, a symbolic link or a hard link to an input is refused before any work.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace contactnn::io {

/// A file given on the command line, with the option that named it (for messages).
struct NamedPath {
  std::string option;  ///< "--output", "--data", "report file 'errors.csv'"...
  std::filesystem::path path;
};

/// True when `a` and `b` are the same existing regular file (same device and inode, symbolic links
/// followed, hard links included), or, if either does not exist yet, the same path once symbolic links
/// and "." / ".." are resolved. Devices, FIFOs and other non-regular files are never "the same file": they
/// are written in place, never replaced, so an input cannot be destroyed through them.
[[nodiscard]] bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

/// Refuses, with InvalidArgument (exit 2) naming both options and both paths, an output that is the same
/// file as an input ("refusing to overwrite an input") or as another output. Entries with an empty path are
/// skipped. Call it before any work.
void require_distinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

}  // namespace contactnn::io
