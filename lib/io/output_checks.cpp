#include "io/output_checks.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/error.hpp"
#include "io/atomic_output.hpp"

namespace contactnn::io {

namespace {

namespace fs = std::filesystem;

std::string in_quotes(const fs::path& p) { return "'" + p.string() + "'"; }

/// The path absolute, with symbolic links and dots resolved as far as it exists.
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) r = fs::absolute(p, ec).lexically_normal();
  if (!r.has_filename() && r.has_parent_path() && r != r.root_path()) r = r.parent_path();  // "dir/" -> "dir"
  return r;
}

/// True when `inner` is `outer` or lies under it (both resolved, absolute).
bool under(const fs::path& inner, const fs::path& outer) {
  const auto [o, i] = std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
  return o == outer.end();
}

/// Where an input lies, as the places a directory replaced whole could hold it: the file itself (links
/// followed) and the name it was given by (its directory resolved, the last link not followed).
std::vector<fs::path> places_of(const fs::path& input) {
  std::vector<fs::path> places = {resolved(input)};
  const fs::path absolute = fs::absolute(input).lexically_normal();
  if (absolute.has_filename()) places.push_back(resolved(absolute.parent_path()) / absolute.filename());
  return places;
}

/// Makes and removes a directory in `dir`: IoError naming `option` and `shown` with the system's reason when
/// the file system refuses (read-only, no permission, /proc).
void probe(const std::string& option, const fs::path& shown, const fs::path& dir) {
  const fs::path name = dir / (".contactnn-probe." + std::to_string(::getpid()) + ".tmp");
  CONTACTNN_REQUIRE_AS(IoError, ::mkdir(name.c_str(), 0700) == 0,
                       option << " " << in_quotes(shown) << ": cannot write in " << in_quotes(dir) << ": "
                              << std::strerror(errno));
  ::rmdir(name.c_str());
}

/// The exit-4 checks of one output directory (see require_outputs).
void require_writable_directory(const OutputDirectory& d) {
  std::error_code ec;
  const fs::file_status status = fs::status(d.path, ec);
  if (!ec && status.type() != fs::file_type::not_found) {
    CONTACTNN_REQUIRE_AS(IoError, status.type() == fs::file_type::directory,
                         d.option << " " << in_quotes(d.path)
                                  << ": cannot write a directory there: it exists and is "
                                     "not a directory");
    const fs::path target = resolved(d.path);
    if (d.replaced_whole) {
      probe(d.option, d.path, target.parent_path());  // the new report is built beside the old one
    } else {
      probe(d.option, d.path, target);
      for (const std::string& name : d.names) require_writable(d.path / name);
    }
    return;
  }
  // Missing: the nearest existing ancestor must be a directory in which one can be made.
  fs::path ancestor = fs::absolute(d.path, ec).lexically_normal();
  if (!ancestor.has_filename()) ancestor = ancestor.parent_path();
  while (ancestor.has_parent_path() && ancestor != ancestor.root_path()) {
    ancestor = ancestor.parent_path();
    const fs::file_status s = fs::status(ancestor, ec);
    if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory) {
      throw IoError(d.option + " " + in_quotes(d.path) + ": cannot check " + in_quotes(ancestor) + ": " +
                    ec.message());
    }
    if (s.type() == fs::file_type::not_found) continue;
    CONTACTNN_REQUIRE_AS(IoError, s.type() == fs::file_type::directory,
                         d.option << " " << in_quotes(d.path) << ": cannot make the directory: "
                                  << in_quotes(ancestor) << " is not a directory");
    probe(d.option, d.path, ancestor);
    return;
  }
}

}  // namespace

void require_outputs(const std::vector<NamedPath>& files, const std::vector<OutputDirectory>& directories,
                     const std::vector<NamedPath>& inputs) {
  // 1. Exit 2: outputs that are inputs or each other; directories that are or hold an input.
  std::vector<NamedPath> all_files = files;
  for (const OutputDirectory& d : directories) {
    if (d.path.empty()) continue;
    const fs::path dir = resolved(d.path);
    for (const NamedPath& in : inputs) {
      if (in.path.empty()) continue;
      const bool is = same_file(d.path, in.path) || resolved(in.path) == dir;
      CONTACTNN_REQUIRE_AS(InvalidArgument, !is,
                           d.option << " " << in_quotes(d.path) << " and " << in.option << " "
                                    << in_quotes(in.path)
                                    << " are the same file: refusing to overwrite an input");
      if (!d.replaced_whole) continue;
      for (const fs::path& place : places_of(in.path)) {
        CONTACTNN_REQUIRE_AS(
            InvalidArgument, !under(place, dir),
            d.option << " " << in_quotes(d.path) << " holds " << in.option << " " << in_quotes(in.path)
                     << ": the directory is replaced whole, so it must not hold an input (choose a "
                        "new or empty directory)");
      }
    }
    for (const NamedPath& f : files) {
      CONTACTNN_REQUIRE_AS(InvalidArgument, f.path.empty() || resolved(f.path) != dir,
                           d.option << " " << in_quotes(d.path) << " and " << f.option << " "
                                    << in_quotes(f.path)
                                    << " are the same path: a directory and a file cannot share it");
    }
    for (const std::string& name : d.names) {
      all_files.push_back({d.option + " file '" + name + "'", d.path / name});
    }
  }
  require_distinct(all_files, inputs);

  // 2. Exit 4: what the file system will not take.
  for (const OutputDirectory& d : directories) {
    if (!d.path.empty()) require_writable_directory(d);
  }
  for (const NamedPath& f : files) {
    if (f.path.empty()) continue;
    try {
      require_writable(f.path);
    } catch (const IoError& e) {
      throw IoError(f.option + ": " + e.what());
    }
  }
}

void make_output_directory(const std::string& option, const std::filesystem::path& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  CONTACTNN_REQUIRE_AS(IoError, !ec,
                       option << " " << in_quotes(path) << ": cannot make the directory: " << ec.message());
}

}  // namespace contactnn::io
