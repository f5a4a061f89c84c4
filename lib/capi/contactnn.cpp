// The C interface (contactnn/contactnn.h) over search::LocalSearch and io::read_network_model. Each entry
// point is a boundary: exceptions become return codes and a thread-local message, nothing else leaves.
#include "contactnn/contactnn.h"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "capi_internal.hpp"
#include "core/conventions.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/face_network_file.hpp"
#include "io/network_model_file.hpp"
#include "io/plan_file.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "search/network_model.hpp"
#include "search/search_options.hpp"

using namespace contactnn;

// The header's numbers are contactnn's own: a change on either side must fail here, not in an FE code.
static_assert(CONTACTNN_ERROR_INTERNAL == static_cast<int>(ExitCode::kInternal));
static_assert(CONTACTNN_ERROR_INVALID_ARGUMENT == static_cast<int>(ExitCode::kUsage));
static_assert(CONTACTNN_ERROR_FORMAT == static_cast<int>(ExitCode::kBadInput));
static_assert(CONTACTNN_ERROR_IO == static_cast<int>(ExitCode::kIo));
static_assert(CONTACTNN_ERROR_NUMERICAL == static_cast<int>(ExitCode::kNumerical));
static_assert(CONTACTNN_STATUS_OK == static_cast<int>(Status::kOk));
static_assert(CONTACTNN_STATUS_OUTSIDE == static_cast<int>(Status::kOutside));
static_assert(CONTACTNN_STATUS_NO_CONVERGENCE == static_cast<int>(Status::kNoConvergence));
static_assert(CONTACTNN_STATUS_DEGENERATE == static_cast<int>(Status::kDegenerate));
static_assert(CONTACTNN_STATUS_INVALID == static_cast<int>(Status::kInvalid));
static_assert(CONTACTNN_STATUS_OUT_OF_DOMAIN == static_cast<int>(Status::kOutOfDomain));
static_assert(CONTACTNN_STATUS_NO_SEGMENT == static_cast<int>(Status::kNoSegment));
static_assert(CONTACTNN_STATUS_NO_SEGMENT + 1 == kStatusCount);
static_assert(CONTACTNN_SURFACE_BILINEAR == static_cast<int>(SurfaceKind::kBilinear));
static_assert(CONTACTNN_SURFACE_GREGORY == static_cast<int>(SurfaceKind::kGregory));
// iterations are written straight into the caller's int array.
static_assert(std::is_same_v<std::int32_t, int>);
// A network_file longer than Linux's PATH_MAX names no file: refused before it is echoed or opened.
using capi::kMaxPathBytes;
/// A run of at most this many queries keeps its statuses on the stack (contactnn_search_run).
constexpr std::size_t kStackStatuses = 64;

namespace contactnn::capi {

namespace {
/// HDF5 as Debian builds it is not thread-safe: one network file read at a time.
std::mutex g_network_read_mutex;
}  // namespace

std::unique_ptr<const search::NetworkModel> load_network(const std::string& path) {
  const std::lock_guard<std::mutex> lock(g_network_read_mutex);
  return io::read_network_model(path);
}

}  // namespace contactnn::capi

namespace {
/// The check value of a live handle ("cnnsrch" and a version byte). Written at creation, cleared at destroy.
constexpr std::uint64_t kLiveHandle = 0x636e6e7372636801;
}  // namespace

/// The handle: a check value, the network (if any) and the search that points to it, never changed after
/// creation. `check` comes first: a pointer to something else, or to a destroyed handle (the check cleared,
/// and the allocator's own bookkeeping written over the first bytes of freed memory), shows another value.
struct contactnn_search {
  std::uint64_t check = kLiveHandle;
  std::unique_ptr<const search::NetworkModel> network;
  std::optional<search::LocalSearch> search;  ///< CONTACTNN_SURFACE_BILINEAR, _GREGORY
  std::unique_ptr<const search::FaceNetwork> face_network;
  std::optional<search::FaceSearch> face;  ///< CONTACTNN_SURFACE_TRI3, _TRI6, _QUAD8
  int surface = 0;                         ///< the CONTACTNN_SURFACE_* it was created for
  int threads = 0;
};

namespace {

thread_local std::string t_last_error;
/// Set when even the message could not be stored (no memory for it).
thread_local bool t_last_error_lost = false;

int record_error(int code, const char* message) noexcept {
  try {
    t_last_error.assign(message);
    t_last_error_lost = false;
  } catch (...) {
    t_last_error.clear();
    t_last_error_lost = true;
  }
  return code;
}

/// Runs `body`: exceptions to return codes and this thread's message (capi_internal.hpp, shared with the
/// contact search handle's entry points).
using capi::guarded;

using capi::load_network;

/// Whether `handle` points to a live search: its check value, read as bytes (a pointer that is not a handle
/// may point to anything readable, aligned or not).
bool is_live(const contactnn_search* handle) noexcept {
  if (handle == nullptr) return false;
  std::uint64_t check = 0;
  std::memcpy(&check, static_cast<const void*>(handle), sizeof check);
  return check == kLiveHandle;
}

/// `handle` checked: INVALID_ARGUMENT for NULL and for a pointer whose check value is not a live handle's.
const contactnn_search& live_handle(const char* function, const contactnn_search* handle) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, handle != nullptr, function << ": search is NULL");
  CONTACTNN_REQUIRE_AS(InvalidArgument, is_live(handle),
                       function << ": search is not a live handle (destroyed already, or not one that "
                                   "contactnn_search_create wrote)");
  return *handle;
}

/// The team of a run: the handle's thread count, or OpenMP's default (OMP_NUM_THREADS, which may say
/// anything) capped at CONTACTNN_MAX_THREADS: libgomp fails inside the parallel region when it cannot start
/// the team.
int run_threads(const contactnn_search& handle) {
  if (handle.threads > 0) return handle.threads;
  return std::clamp(omp_get_max_threads(), 1, static_cast<int>(CONTACTNN_MAX_THREADS));
}

/// The method named by the caller. The message of a name that does not parse quotes it short (a 10 MB string
/// would otherwise be echoed whole, once per place it is named).
search::Method parse_method(std::string_view method) {
  if (method.size() <= kQuotedBytes) return search::Method::parse(method);
  try {
    return search::Method::parse(method);
  } catch (const InvalidArgument&) {
    throw InvalidArgument("contactnn_search_create: method " + quote_text(method) +
                          " is not a local-search method (contactnn.h lists them)");
  }
}

/// `options`, or where it is NULL the library's defaults written into `defaults`; its threads checked
/// (require_threads, naming `function`).
const contactnn_options* options_or_defaults(const contactnn_options* options, contactnn_options& defaults,
                                             const char* function) {
  if (options == nullptr) {
    contactnn_options_init(&defaults);
    options = &defaults;
  }
  capi::require_threads(options->threads, function);
  return options;
}

search::SearchOptions to_search_options(const contactnn_options& o) {
  search::SearchOptions s;
  s.max_iterations = o.max_iterations;
  s.tol_param = o.tol_param;
  s.domain_margin = o.domain_margin;
  s.gregory_box_margin = o.gregory_box_margin;
  s.bilinear_box_margin = o.bilinear_box_margin;
  s.max_step_widths = o.max_step_widths;
  s.max_halvings = o.max_halvings;
  s.check_domain = o.check_domain != 0;
  s.min_parallel_count = o.min_parallel_count;
  return s;
}

template <class Real>
int run(const char* function, const contactnn_search* handle, std::size_t count, const Real* raw, Real* param,
        Real* gap, int* status, int* iterations) noexcept {
  return guarded(function, [&] {
    const contactnn_search& live = live_handle(function, handle);
    if (count == 0) return;
    CONTACTNN_REQUIRE_AS(InvalidArgument, raw != nullptr && param != nullptr && status != nullptr,
                         function << ": raw, param and status must not be NULL for count = " << count
                                  << " (raw " << (raw ? "set" : "NULL") << ", param "
                                  << (param ? "set" : "NULL") << ", status " << (status ? "set" : "NULL")
                                  << ")");
    const auto columns = static_cast<std::size_t>(contactnn_raw_columns(live.surface));
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, count <= std::numeric_limits<std::size_t>::max() / (columns * sizeof(Real)),
        function << ": count = " << count << " queries of " << columns << " values overflow size_t");
    // LocalSearch writes one byte per status; the C caller gets ints. A few queries (an FE code's one pair
    // per call) keep theirs on the stack, with no heap allocation, and never ask OpenMP for a team: below
    // min_parallel_count the search runs on the calling thread whatever the thread count.
    const search::SearchOptions& options = live.face ? live.face->options() : live.search->options();
    const int threads = count < options.min_parallel_count ? 1 : run_threads(live);
    Status few[kStackStatuses];
    std::vector<Status> many;
    Status* statuses = few;
    if (count > kStackStatuses) {
      many.resize(count);
      statuses = many.data();
    }
    if (live.face) {
      live.face->run(count, raw, search::Results<Real>{param, gap, statuses, iterations}, threads);
    } else {
      live.search->run(count, raw, search::Results<Real>{param, gap, statuses, iterations}, threads);
    }
    for (std::size_t i = 0; i < count; ++i) status[i] = static_cast<int>(statuses[i]);
  });
}

}  // namespace

extern "C" {

const char* contactnn_version(int* major, int* minor, int* patch) {
  if (major != nullptr) *major = CONTACTNN_VERSION_MAJOR;
  if (minor != nullptr) *minor = CONTACTNN_VERSION_MINOR;
  if (patch != nullptr) *patch = CONTACTNN_VERSION_PATCH;
  return CONTACTNN_VERSION_STRING;
}

const char* contactnn_last_error(void) {
  return t_last_error_lost ? "out of memory (the error message was lost)" : t_last_error.c_str();
}

int contactnn_set_last_error(int code, const char* message) {
  return record_error(code, message != nullptr ? message : "");
}

const char* contactnn_status_name(int status) {
  if (status < 0 || status >= kStatusCount) return "unknown";
  // to_string returns views of string literals: null-terminated.
  return to_string(static_cast<Status>(status)).data();
}

int contactnn_raw_columns(int surface) {
  if (surface == CONTACTNN_SURFACE_BILINEAR) return search::LocalSearch::raw_columns(SurfaceKind::kBilinear);
  if (surface == CONTACTNN_SURFACE_GREGORY) return search::LocalSearch::raw_columns(SurfaceKind::kGregory);
  if (surface == CONTACTNN_SURFACE_TRI3) return search::face_raw_columns(search::FaceKind::kTri3);
  if (surface == CONTACTNN_SURFACE_TRI6) return search::face_raw_columns(search::FaceKind::kTri6);
  if (surface == CONTACTNN_SURFACE_QUAD8) return search::face_raw_columns(search::FaceKind::kQuad8);
  return 0;
}

int contactnn_options_init(contactnn_options* options) {
  return guarded("contactnn_options_init", [&] {
    CONTACTNN_REQUIRE_AS(InvalidArgument, options != nullptr, "contactnn_options_init: options is NULL");
    const search::SearchOptions d;
    *options = contactnn_options{};
    options->threads = 0;
    options->check_domain = d.check_domain ? 1 : 0;
    options->max_iterations = d.max_iterations;
    options->max_halvings = d.max_halvings;
    options->tol_param = d.tol_param;
    options->domain_margin = d.domain_margin;
    options->gregory_box_margin = d.gregory_box_margin;
    options->bilinear_box_margin = d.bilinear_box_margin;
    options->max_step_widths = d.max_step_widths;
    options->min_parallel_count = d.min_parallel_count;
  });
}

int contactnn_search_create(contactnn_search** out, int surface, const char* method, const char* network_file,
                            const contactnn_options* options) {
  return guarded("contactnn_search_create", [&] {
    CONTACTNN_REQUIRE_AS(InvalidArgument, out != nullptr,
                         "contactnn_search_create: search (where the handle goes) is NULL");
    *out = nullptr;
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, contactnn_raw_columns(surface) > 0,
        "contactnn_search_create: surface = "
            << surface
            << ", expected CONTACTNN_SURFACE_BILINEAR (0), _GREGORY (1), _TRI3 (2), _TRI6 (3) or "
               "_QUAD8 (4)");
    CONTACTNN_REQUIRE_AS(InvalidArgument, method != nullptr, "contactnn_search_create: method is NULL");
    const search::Method parsed = parse_method(method);
    const bool has_file = network_file != nullptr && network_file[0] != '\0';
    CONTACTNN_REQUIRE_AS(InvalidArgument, has_file || !parsed.needs_network(),
                         "contactnn_search_create: method " << quote_text(method)
                                                            << " needs a network file; network_file is "
                                                            << (network_file == nullptr ? "NULL" : "empty"));
    CONTACTNN_REQUIRE_AS(InvalidArgument, !has_file || std::strlen(network_file) <= kMaxPathBytes,
                         "contactnn_search_create: network_file "
                             << quote_text(network_file) << " is longer than any path (" << kMaxPathBytes
                             << " bytes)");
    contactnn_options defaults{};
    options = options_or_defaults(options, defaults, "contactnn_search_create");

    auto handle = std::make_unique<contactnn_search>();
    handle->threads = options->threads;
    handle->surface = surface;
    if (surface >= CONTACTNN_SURFACE_TRI3) {
      // FaceSearch (search/face_search.hpp): a face network file (io/face_network_file.hpp) of the same face
      // type.
      const auto face = static_cast<search::FaceKind>(surface - CONTACTNN_SURFACE_TRI3);
      CONTACTNN_REQUIRE_AS(InvalidArgument, face != search::FaceKind::kTri3 || !parsed.needs_network(),
                           "contactnn_search_create: method "
                               << quote_text(method)
                               << " on tri3 faces: a flat triangle's closed form is "
                                  "exact (method closed_form), no network is made for it");
      if (has_file) {
        handle->face_network = io::load_face_network(network_file);
        CONTACTNN_REQUIRE_AS(InvalidArgument, handle->face_network->face() == face,
                             "contactnn_search_create: '" << network_file << "' is a "
                                                          << search::to_string(handle->face_network->face())
                                                          << " network, the search is for "
                                                          << search::to_string(face) << " faces");
      }
      handle->face.emplace(face, parsed, to_search_options(*options), handle->face_network.get());
      *out = handle.release();
      return;
    }
    const auto kind = static_cast<SurfaceKind>(surface);
    if (has_file) {
      handle->network = load_network(network_file);
      CONTACTNN_REQUIRE_AS(InvalidArgument, handle->network->surface() == kind,
                           "contactnn_search_create: '"
                               << network_file << "' is a " << to_string(handle->network->surface())
                               << " network, the search is for " << to_string(kind) << " surfaces");
    }
    handle->search.emplace(kind, parsed, to_search_options(*options), handle->network.get());
    *out = handle.release();
  });
}

void contactnn_search_destroy(contactnn_search* handle) {
  if (handle == nullptr) return;
  if (!is_live(handle)) {
    // Destroyed already (or not a handle): freeing it again would corrupt the heap.
    record_error(CONTACTNN_ERROR_INVALID_ARGUMENT,
                 "contactnn_search_destroy: search is not a live handle (destroyed already, or not one that "
                 "contactnn_search_create wrote); nothing was freed");
    return;
  }
  // A volatile store: one the compiler may not drop as dead before the memory is freed.
  *static_cast<volatile std::uint64_t*>(&handle->check) = 0;
  delete handle;
}

int contactnn_search_run(const contactnn_search* handle, size_t count, const double* raw, double* param,
                         double* gap, int* status, int* iterations) {
  return run("contactnn_search_run", handle, count, raw, param, gap, status, iterations);
}

int contactnn_search_run_float(const contactnn_search* handle, size_t count, const float* raw, float* param,
                               float* gap, int* status, int* iterations) {
  return run("contactnn_search_run_float", handle, count, raw, param, gap, status, iterations);
}

int contactnn_search_surface(const contactnn_search* handle) {
  return is_live(handle) ? handle->surface : -1;
}

int contactnn_search_create_from_plan(contactnn_search** out, const char* plan_file,
                                      const contactnn_options* options) {
  return guarded("contactnn_search_create_from_plan", [&] {
    CONTACTNN_REQUIRE_AS(InvalidArgument, out != nullptr,
                         "contactnn_search_create_from_plan: search (where the handle goes) is NULL");
    *out = nullptr;
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, plan_file != nullptr && plan_file[0] != '\0',
        "contactnn_search_create_from_plan: plan_file is " << (plan_file == nullptr ? "NULL" : "empty"));
    CONTACTNN_REQUIRE_AS(InvalidArgument, std::strlen(plan_file) <= kMaxPathBytes,
                         "contactnn_search_create_from_plan: plan_file "
                             << quote_text(plan_file) << " is longer than any path (" << kMaxPathBytes
                             << " bytes)");
    contactnn_options defaults{};
    options = options_or_defaults(options, defaults, "contactnn_search_create_from_plan");
    // The plan names its surface, method and network file; read_plan checks the method and that a network is
    // given exactly when the method needs one (FormatError naming the file, the line and the key).
    const io::ScenePlan plan = io::read_plan(plan_file);
    auto handle = std::make_unique<contactnn_search>();
    handle->threads = options->threads;
    handle->surface = static_cast<int>(plan.surface);
    const std::filesystem::path network_file = io::plan_network_path(plan, plan_file);
    if (!network_file.empty()) {
      handle->network = load_network(network_file.string());
      CONTACTNN_REQUIRE_AS(FormatError, handle->network->surface() == plan.surface,
                           "contactnn_search_create_from_plan: '"
                               << network_file.string() << "' is a " << to_string(handle->network->surface())
                               << " network, the plan '" << plan_file << "' is for "
                               << to_string(plan.surface) << " surfaces");
    }
    handle->search.emplace(plan.surface, search::Method::parse(plan.method), to_search_options(*options),
                           handle->network.get());
    *out = handle.release();
  });
}

const char* contactnn_search_method(const contactnn_search* handle) {
  thread_local std::string name;
  try {
    name = !is_live(handle)
               ? std::string()
               : (handle->face ? handle->face->method().name() : handle->search->method().name());
  } catch (...) {
    name.clear();
  }
  return name.c_str();
}

}  // extern "C"
