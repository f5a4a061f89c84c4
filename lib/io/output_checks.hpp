// The one check of a run's outputs that every tool makes before it writes anything (docs/tools.md, "What
// every tool does alike"): an output that is or holds an input is a bad command line (exit 2), an output that
// cannot be written is an I/O failure (exit 4), never an internal error.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/file_identity.hpp"

namespace contactnn::io {

/// A directory a run writes its files into.
struct OutputDirectory {
  std::string option;  ///< "--report", "--output"
  std::filesystem::path path;
  std::vector<std::string> names;  ///< the files the run writes into it
  /// True for a report put in place whole (AtomicDirectory): it replaces the directory, so the directory may
  /// hold no input at any depth. False for a directory that only receives `names` (the rest is left alone).
  bool replaced_whole = false;
};

/// Checks every output of a run against its inputs and the file system, before anything is written, in the
/// same order in every tool:
///  1. InvalidArgument (exit 2): an output file, or a file of an output directory, that is the same file as
///     an input (io::same_file: through symbolic and hard links) or as another output; an output directory
///     that is an input; a directory replaced whole that holds an input at any depth (`--report DIR` beside
///     the run's deck); an output directory that is also an output file.
///  2. IoError (exit 4), naming the option, the path and the system's reason: an output file that cannot be
///     created (its directory missing or not writable, a directory of that name; io::require_writable); an
///     output directory that exists and is not a directory (`--report /dev/null`, `--report deck.inp` when
///     the deck is not an input of this run), lies under something that is not a directory, or cannot be
///     made (`--report /proc/x/y`: a probe directory is made and removed in its nearest existing ancestor),
///     or that exists and receives no file (a probe file is made and removed in it).
/// Nothing is left behind: probes are removed, no directory is made. Entries with an empty path are skipped.
void require_outputs(const std::vector<NamedPath>& files, const std::vector<OutputDirectory>& directories,
                     const std::vector<NamedPath>& inputs);

/// Makes output directory `path` with its parents (after require_outputs): IoError naming `option`, the path
/// and the system's reason when it cannot.
void make_output_directory(const std::string& option, const std::filesystem::path& path);

}  // namespace contactnn::io
