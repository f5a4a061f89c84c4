// The message of the error a call throws, for the tests that check what a refusal says (the file, the line,
// the key).
#pragma once

#include <exception>
#include <string>

namespace contactnn::testing {

/// The message of the E (a contactnn error type) that `call()` throws; `none` when it throws nothing. Another
/// exception is answered "wrong error type: <message>", so that a test expecting E's message fails on it.
template <class E, class Call>
std::string error_message(Call&& call, const std::string& none = "(no error)") {
  try {
    call();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong error type: ") + e.what();
  }
  return none;
}

}  // namespace contactnn::testing
