#include "io/file_identity.hpp"

#include <sys/stat.h>

#include <system_error>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

/// The path with symbolic links and dots resolved as far as it exists; kept as given if even that fails.
std::filesystem::path resolved(const std::filesystem::path& p) {
  std::error_code ec;
  std::filesystem::path r = std::filesystem::weakly_canonical(std::filesystem::absolute(p, ec), ec);
  return ec ? p.lexically_normal() : r;
}

}  // namespace

bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  struct stat sa {
  }, sb{};
  const bool a_exists = ::stat(a.c_str(), &sa) == 0;
  const bool b_exists = ::stat(b.c_str(), &sb) == 0;
  if (a_exists && b_exists) {
    return S_ISREG(sa.st_mode) && S_ISREG(sb.st_mode) && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  }
  if (a_exists != b_exists) return false;
  return resolved(a) == resolved(b);
}

void require_distinct(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedPath& in : inputs) {
      if (in.path.empty() || !same_file(out.path, in.path)) continue;
      throw InvalidArgument(out.option + " '" + out.path.string() + "' and " + in.option + " '" +
                            in.path.string() + "' are the same file: refusing to overwrite an input");
    }
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      const NamedPath& other = outputs[j];
      if (other.path.empty() || !same_file(out.path, other.path)) continue;
      throw InvalidArgument(out.option + " '" + out.path.string() + "' and " + other.option + " '" +
                            other.path.string() +
                            "' are the same file: one output would overwrite the other");
    }
  }
}

}  // namespace contactnn::io
