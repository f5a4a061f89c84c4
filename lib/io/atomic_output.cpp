#include "io/atomic_output.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <set>
#include <system_error>
#include <vector>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

std::atomic<unsigned> g_counter{0};

std::string in_quotes(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::string temporary_name(const std::filesystem::path& target, const std::string& prefix) {
  return "." + prefix + target.filename().string() + "." + std::to_string(::getpid()) + "." +
         std::to_string(g_counter++) + ".tmp";
}

/// `path` with every symbolic link in its last component followed (links in the directories on the way
/// are followed by the system). A link that points nowhere gives the path it points to. `descriptor` is set
/// when the chain reaches a link to an open file descriptor (/dev/stdout -> /proc/self/fd/1, /dev/fd/N):
/// its target names what the descriptor is open on (or "pipe:[N]"), which is to be written through the
/// link, never replaced.
std::filesystem::path follow_links(const std::filesystem::path& path, bool& descriptor) {
  std::filesystem::path current = path;
  descriptor = false;
  for (int depth = 0; depth < 40; ++depth) {
    const std::string text = current.lexically_normal().string();
    if (text.rfind("/dev/fd/", 0) == 0 ||
        (text.rfind("/proc/", 0) == 0 && text.find("/fd/") != std::string::npos)) {
      descriptor = true;
      return current;
    }
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(current, ec);
    if (ec || status.type() != std::filesystem::file_type::symlink) return current;
    const std::filesystem::path target = std::filesystem::read_symlink(current, ec);
    CONTACTNN_REQUIRE_AS(IoError, !ec,
                         "cannot read the symbolic link " << in_quotes(current) << ": " << ec.message());
    current = target.is_absolute() ? target : current.parent_path() / target;
  }
  throw IoError("cannot write " + in_quotes(path) + ": too many levels of symbolic links");
}

std::filesystem::path directory_of(const std::filesystem::path& path) {
  const std::filesystem::path dir = path.parent_path();
  return dir.empty() ? std::filesystem::path(".") : dir;
}

/// Copies the bytes of `from` into the existing non-regular file `to` (a device or FIFO), in place.
void copy_into(const std::filesystem::path& from, const std::filesystem::path& to,
               const std::filesystem::path& shown) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  CONTACTNN_REQUIRE_AS(IoError, in >= 0, "cannot reopen " << in_quotes(from) << ": " << std::strerror(errno));
  const int out = ::open(to.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (out < 0) {
    const int e = errno;
    ::close(in);
    throw IoError("cannot open " + in_quotes(shown) + " for writing: " + std::strerror(e));
  }
  std::vector<char> buffer(1 << 20);
  int error = 0;
  for (;;) {
    const ssize_t got = ::read(in, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      if (got < 0) error = errno;
      break;
    }
    for (ssize_t done = 0; done < got && error == 0;) {
      const ssize_t put = ::write(out, buffer.data() + done, static_cast<std::size_t>(got - done));
      if (put < 0 && errno == EINTR) continue;
      if (put < 0) error = errno;
      if (put > 0) done += put;
    }
    if (error != 0) break;
  }
  ::close(in);
  if (::close(out) != 0 && error == 0) error = errno;
  CONTACTNN_REQUIRE_AS(IoError, error == 0,
                       "cannot write " << in_quotes(shown) << ": " << std::strerror(error));
}

void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);  // makes the rename durable; a file system that cannot is no reason to fail
    ::close(fd);
  }
}

}  // namespace

AtomicOutput::AtomicOutput(std::filesystem::path final_path, Access access)
    : final_path_(std::move(final_path)) {
  CONTACTNN_REQUIRE_AS(IoError, !final_path_.filename().empty(),
                       "output path " << in_quotes(final_path_) << " names no file");
  std::error_code ec;
  // The type of what the path finally names (status follows every link, /proc's descriptor links included).
  const auto status = std::filesystem::status(final_path_, ec);
  const auto type = ec ? std::filesystem::file_type::not_found : status.type();
  CONTACTNN_REQUIRE_AS(IoError, type != std::filesystem::file_type::directory,
                       "cannot write " << in_quotes(final_path_) << ": it is a directory");
  bool descriptor = false;
  target_ = follow_links(final_path_, descriptor);
  in_place_ = type != std::filesystem::file_type::not_found &&
              (type != std::filesystem::file_type::regular || descriptor);
  if (in_place_) target_ = final_path_;  // opened through the links
  if (in_place_ && access == Access::kSequential) {
    write_path_ = target_;
    return;
  }
  std::filesystem::path dir;
  if (in_place_) {
    dir = std::filesystem::temp_directory_path(ec);
    CONTACTNN_REQUIRE_AS(
        IoError, !ec,
        "cannot write " << in_quotes(final_path_) << ": no temporary directory: " << ec.message());
    write_path_ = dir / temporary_name(target_, "contactnn-");
  } else {
    dir = directory_of(target_);
    CONTACTNN_REQUIRE_AS(
        IoError, std::filesystem::is_directory(dir, ec),
        "cannot write " << in_quotes(final_path_) << ": directory " << in_quotes(dir) << " does not exist");
    write_path_ = dir / temporary_name(target_, "");
  }
  registration_ = std::make_unique<TemporaryRegistration>(write_path_);
  has_temporary_ = true;
}

AtomicOutput::~AtomicOutput() {
  if (has_temporary_ && !committed_) {
    std::error_code ec;
    std::filesystem::remove(write_path_, ec);
  }
}

void AtomicOutput::commit() {
  const DeferInterrupts defer;
  commit_unguarded();
}

void AtomicOutput::commit_unguarded() {
  CONTACTNN_REQUIRE(!committed_, "output " << in_quotes(final_path_) << " committed twice");
  if (!has_temporary_) {  // written straight into a device or FIFO
    committed_ = true;
    return;
  }
  if (in_place_) {
    copy_into(write_path_, target_, final_path_);
    std::error_code ec;
    std::filesystem::remove(write_path_, ec);
    committed_ = true;
    registration_.reset();
    return;
  }
  // fsync before rename: after a crash the final name holds either the old file or the whole new one.
  const int fd = ::open(write_path_.c_str(), O_RDONLY | O_CLOEXEC);
  CONTACTNN_REQUIRE_AS(
      IoError, fd >= 0,
      "cannot reopen " << in_quotes(write_path_) << " to flush it: " << std::strerror(errno));
  struct stat existing {};
  if (::stat(target_.c_str(), &existing) == 0 && S_ISREG(existing.st_mode)) {
    ::fchmod(fd, existing.st_mode & 07777);  // a replaced file keeps its permissions (best effort)
  }
  const int sync_result = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  CONTACTNN_REQUIRE_AS(IoError, sync_result == 0,
                       "cannot flush " << in_quotes(write_path_) << ": " << std::strerror(sync_errno));
  std::error_code ec;
  std::filesystem::rename(write_path_, target_, ec);
  CONTACTNN_REQUIRE_AS(
      IoError, !ec,
      "cannot rename " << in_quotes(write_path_) << " to " << in_quotes(final_path_) << ": " << ec.message());
  committed_ = true;
  registration_.reset();
  sync_directory(directory_of(target_));
}

void commit_together(std::initializer_list<AtomicOutput*> outputs) {
  const DeferInterrupts defer;
  // Lock each directory once, in a fixed order, so that two runs can never wait on each other.
  std::set<std::string> directories;
  for (const AtomicOutput* o : outputs) {
    if (o != nullptr && !o->in_place_) directories.insert(directory_of(o->target_).string());
  }
  std::vector<int> locks;
  for (const std::string& dir : directories) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) continue;  // the lock guards against a concurrent run only; the commit itself goes on
    while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
    }
    locks.push_back(fd);
  }
  const auto unlock = [&] {
    for (const int fd : locks) ::close(fd);  // closing releases the lock
    locks.clear();
  };
  try {
    for (AtomicOutput* o : outputs) {
      if (o != nullptr) o->commit_unguarded();
    }
  } catch (...) {
    unlock();
    throw;
  }
  unlock();
}

bool written_in_place(const std::filesystem::path& path) {
  try {
    return AtomicOutput(path, AtomicOutput::Access::kSequential).in_place();
  } catch (const Error&) {
    return false;
  }
}

void require_writable(const std::filesystem::path& path) {
  AtomicOutput probe(path, AtomicOutput::Access::kSequential);
  if (probe.in_place()) return;
  const int fd = ::open(probe.write_path().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  CONTACTNN_REQUIRE_AS(IoError, fd >= 0,
                       "cannot write " << in_quotes(path) << ": cannot create a file in directory "
                                       << in_quotes(directory_of(probe.write_path())) << ": "
                                       << std::strerror(errno));
  ::close(fd);  // the probe's destructor removes it
}

AtomicDirectory::AtomicDirectory(std::filesystem::path final_path,
                                 std::initializer_list<std::string> owned_names,
                                 const std::string& option_name)
    : final_path_(std::move(final_path)) {
  std::error_code ec;
  target_ = std::filesystem::weakly_canonical(std::filesystem::absolute(final_path_), ec);
  CONTACTNN_REQUIRE_AS(IoError, !ec,
                       "cannot use " << in_quotes(final_path_) << " as a directory: " << ec.message());
  if (!target_.has_filename()) target_ = target_.parent_path();
  CONTACTNN_REQUIRE_AS(IoError, target_.has_parent_path() && target_ != target_.root_path(),
                       "cannot use " << in_quotes(final_path_) << " as an output directory: it is the root");
  const auto status = std::filesystem::status(target_, ec);
  if (!ec && status.type() != std::filesystem::file_type::not_found) {
    CONTACTNN_REQUIRE_AS(IoError, status.type() == std::filesystem::file_type::directory,
                         "cannot write " << in_quotes(final_path_) << ": it exists and is not a directory");
    const std::set<std::string> owned(owned_names);
    for (const auto& entry : std::filesystem::directory_iterator(target_, ec)) {
      const std::string name = entry.path().filename().string();
      const bool stale_temporary = name.size() > 5 && name.front() == '.' && name.ends_with(".tmp");
      const bool ours = (owned.count(name) > 0 && entry.is_regular_file(ec)) || stale_temporary;
      CONTACTNN_REQUIRE_AS(InvalidArgument, ours,
                           option_name
                               << " " << in_quotes(final_path_) << " holds " << in_quotes(name)
                               << ", which is not part of a report: the directory is replaced whole, so it "
                                  "must hold nothing else (choose a new or empty directory)");
    }
    CONTACTNN_REQUIRE_AS(IoError, !ec, "cannot list " << in_quotes(final_path_) << ": " << ec.message());
  } else {
    std::filesystem::create_directories(target_.parent_path(), ec);
    CONTACTNN_REQUIRE_AS(
        IoError, !ec, "cannot create directory " << in_quotes(target_.parent_path()) << ": " << ec.message());
  }
  write_path_ = target_.parent_path() / temporary_name(target_, "");
  registration_ = std::make_unique<TemporaryRegistration>(write_path_, true);
  CONTACTNN_REQUIRE_AS(IoError, ::mkdir(write_path_.c_str(), 0777) == 0,
                       "cannot create directory " << in_quotes(write_path_) << ": " << std::strerror(errno));
}

AtomicDirectory::~AtomicDirectory() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove_all(write_path_, ec);
  }
}

void AtomicDirectory::commit() {
  const DeferInterrupts defer;
  sync_directory(write_path_);
  std::error_code ec;
  const bool replacing = std::filesystem::exists(target_, ec);
  if (!replacing) {
    std::filesystem::rename(write_path_, target_, ec);
    CONTACTNN_REQUIRE_AS(IoError, !ec,
                         "cannot rename " << in_quotes(write_path_) << " to " << in_quotes(final_path_)
                                          << ": " << ec.message());
  } else if (::renameat2(AT_FDCWD, write_path_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
    // No atomic exchange on this file system: move the old directory aside, then the new one in.
    CONTACTNN_REQUIRE_AS(IoError, errno == EINVAL || errno == ENOSYS || errno == ENOTSUP,
                         "cannot exchange " << in_quotes(write_path_) << " and " << in_quotes(final_path_)
                                            << ": " << std::strerror(errno));
    const std::filesystem::path aside = target_.parent_path() / temporary_name(target_, "old-");
    const TemporaryRegistration aside_registration(aside, true);
    std::filesystem::rename(target_, aside, ec);
    CONTACTNN_REQUIRE_AS(IoError, !ec,
                         "cannot move " << in_quotes(final_path_) << " aside: " << ec.message());
    std::filesystem::rename(write_path_, target_, ec);
    if (ec) {
      std::error_code ignored;
      std::filesystem::rename(aside, target_, ignored);
      throw IoError("cannot rename " + in_quotes(write_path_) + " to " + in_quotes(final_path_) + ": " +
                    ec.message());
    }
    std::filesystem::remove_all(aside, ec);
  } else {
    std::filesystem::remove_all(write_path_, ec);  // the previous report, exchanged into the temporary name
  }
  committed_ = true;
  registration_.reset();
  sync_directory(target_.parent_path());
}

}  // namespace contactnn::io
