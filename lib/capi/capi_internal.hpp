// What the C interface's entry points share (contactnn.cpp, contact_search.cpp): each entry point is a
// boundary where exceptions become return codes and this thread's message (contactnn_last_error), nothing
// else leaves.
#pragma once

#include <cstddef>
#include <exception>
#include <memory>
#include <new>
#include <string>

#include "contactnn/contactnn.h"
#include "core/error.hpp"

namespace contactnn::search {
class NetworkModel;
}  // namespace contactnn::search

namespace contactnn::capi {

/// A path longer than Linux's PATH_MAX names no file: refused before it is echoed or opened.
inline constexpr std::size_t kMaxPathBytes = 4096;

/// io::read_network_model(path), one read at a time (HDF5 as Debian builds it is not thread-safe); shared by
/// the searches' and the contact handles' creation (contactnn.cpp).
std::unique_ptr<const search::NetworkModel> load_network(const std::string& path);

/// Runs `body` and turns what it throws into a return code and this thread's message (recorded through
/// contactnn_set_last_error, the one place that stores it).
template <class Body>
int guarded(const char* function, Body&& body) noexcept {
  try {
    body();
    return CONTACTNN_SUCCESS;
  } catch (const Error& e) {
    return contactnn_set_last_error(e.exit_code(), e.what());
  } catch (const std::bad_alloc&) {
    return contactnn_set_last_error(CONTACTNN_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    try {
      return contactnn_set_last_error(CONTACTNN_ERROR_INTERNAL,
                                      (std::string(function) + ": internal error: " + e.what()).c_str());
    } catch (...) {
      return contactnn_set_last_error(CONTACTNN_ERROR_INTERNAL, "internal error");
    }
  } catch (...) {
    return contactnn_set_last_error(CONTACTNN_ERROR_INTERNAL, "internal error: an unknown exception");
  }
}

/// A handle's options.threads at most CONTACTNN_MAX_THREADS (0 or less: OpenMP's default), else
/// InvalidArgument naming `function`.
inline void require_threads(int threads, const char* function) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, threads <= CONTACTNN_MAX_THREADS,
                       function << ": options.threads = " << threads
                                << ", expected at most CONTACTNN_MAX_THREADS (" << CONTACTNN_MAX_THREADS
                                << "; 0 or less: OpenMP's default)");
}

}  // namespace contactnn::capi
