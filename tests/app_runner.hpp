// Shared by the tests that run the built tools (evaluate-net's, scene-study's): a file's text, and a shell
// command run with its output in a log file.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace contactnn::testing {

/// The whole text of `p` ("" when it cannot be read).
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs a shell command, stdout and stderr into `log`; returns the exit status (-1 when it did not exit).
inline int run(const std::string& command, const std::filesystem::path& log) {
  const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace contactnn::testing
