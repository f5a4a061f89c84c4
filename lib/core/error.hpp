// contactnn::Error and its subclasses, and the always-on REQUIRE macro.
//
// Everything below `main` reports failure by throwing one of these; only the apps catch, print
// `error: <what()>` and return the exit code the exception carries. The exit codes are part of the
// documented interface (docs/tools.md, `--help`):
//   0  success
//   1  unexpected internal error (a bug: please report)
//   2  bad command line or config file (unknown option or key, value out of range, missing file given
//      as an option; CLI11's own parse errors are mapped onto this code by the apps)
//   3  bad input data: malformed CSV, wrong HDF5 schema/shape, a file of the wrong kind
//   4  I/O failure: cannot open, read, write or rename a file
//   5  numerical failure: a non-finite loss or value where a finite one is required
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace contactnn {

/// Exit codes carried by the exceptions below (see the header comment).
enum class ExitCode : int {
  kOk = 0,
  kInternal = 1,
  kUsage = 2,
  kBadInput = 3,
  kIo = 4,
  kNumerical = 5,
};

/// Base of every contactnn exception. `exit_code()` is what an app returns when it catches it.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, ExitCode code = ExitCode::kInternal)
      : std::runtime_error(message), code_(code) {}
  [[nodiscard]] int exit_code() const noexcept { return static_cast<int>(code_); }

 private:
  ExitCode code_;
};

/// A caller passed a value outside its documented range (a programming or configuration error).
class InvalidArgument : public Error {
 public:
  explicit InvalidArgument(const std::string& m) : Error(m, ExitCode::kUsage) {}
};

/// A file's content is not what was expected: a CSV field that does not parse, a missing column, an HDF5
/// dataset of the wrong shape or schema version, a network file where a dataset was expected.
class FormatError : public Error {
 public:
  explicit FormatError(const std::string& m) : Error(m, ExitCode::kBadInput) {}
};

/// The operating system refused: cannot open, read, write or rename a file.
class IoError : public Error {
 public:
  explicit IoError(const std::string& m) : Error(m, ExitCode::kIo) {}
};

/// A computation produced a non-finite value where a finite one is required (e.g. a diverging loss).
class NumericalError : public Error {
 public:
  explicit NumericalError(const std::string& m) : Error(m, ExitCode::kNumerical) {}
};

}  // namespace contactnn

/// Always-on check (also in Release). `msg` is a stream expression: REQUIRE(n > 0, "n = " << n).
/// Throws contactnn::InvalidArgument naming the failed condition, the message and the source location: for
/// an internal invariant. A caller's bad argument that users see (a method name, an option of the C
/// interface) takes REQUIRE_AS(InvalidArgument, ...), whose message is the user's alone.
#define CONTACTNN_REQUIRE(cond, msg)                                                                        \
  do {                                                                                                      \
    if (!(cond)) {                                                                                          \
      std::ostringstream contactnn_require_os_;                                                             \
      contactnn_require_os_ << msg << " [requirement '" #cond "' failed at " << __FILE__ << ":" << __LINE__ \
                            << "]";                                                                         \
      throw ::contactnn::InvalidArgument(contactnn_require_os_.str());                                      \
    }                                                                                                       \
  } while (false)

/// Same, throwing a chosen contactnn exception type: REQUIRE_AS(FormatError, ok, "...").
#define CONTACTNN_REQUIRE_AS(ExceptionType, cond, msg)  \
  do {                                                  \
    if (!(cond)) {                                      \
      std::ostringstream contactnn_require_os_;         \
      contactnn_require_os_ << msg;                     \
      throw ExceptionType(contactnn_require_os_.str()); \
    }                                                   \
  } while (false)
