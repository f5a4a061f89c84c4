#include "io/atomic_output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <system_error>

#include "core/error.hpp"

namespace contactnn::io {

namespace {
std::atomic<unsigned> g_counter{0};
}

AtomicOutput::AtomicOutput(std::filesystem::path final_path) : final_path_(std::move(final_path)) {
  CONTACTNN_REQUIRE_AS(IoError, !final_path_.filename().empty(), "output path '" << final_path_.string() << "' names no file");
  std::filesystem::path dir = final_path_.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  CONTACTNN_REQUIRE_AS(IoError, std::filesystem::is_directory(dir, ec),
                       "cannot write '" << final_path_.string() << "': directory '" << dir.string()
                                        << "' does not exist");
  temp_path_ = dir / ("." + final_path_.filename().string() + "." + std::to_string(::getpid()) + "." +
                      std::to_string(g_counter++) + ".tmp");
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_path_, ec);
  }
}

void AtomicOutput::commit() {
  // fsync before rename: after a crash the final name holds either the old file or the whole new one.
  const int fd = ::open(temp_path_.c_str(), O_RDONLY);
  CONTACTNN_REQUIRE_AS(IoError, fd >= 0,
                       "cannot reopen '" << temp_path_.string() << "' to flush it: " << std::strerror(errno));
  const int sync_result = ::fsync(fd);
  ::close(fd);
  CONTACTNN_REQUIRE_AS(IoError, sync_result == 0,
                       "cannot flush '" << temp_path_.string() << "': " << std::strerror(errno));
  std::error_code ec;
  std::filesystem::rename(temp_path_, final_path_, ec);
  CONTACTNN_REQUIRE_AS(IoError, !ec,
                       "cannot rename '" << temp_path_.string() << "' to '" << final_path_.string()
                                         << "': " << ec.message());
  committed_ = true;
}

}  // namespace contactnn::io
