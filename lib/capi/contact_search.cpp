// The C interface's contact search handle (contactnn/contactnn.h, contactnn_contact_*) over
// contact::ContactSearch. Each entry point is a boundary: exceptions become return codes and this thread's
// message (capi_internal.hpp), nothing else leaves; nothing is written to a caller's array before every
// argument has been checked.
#include "contact/contact_search.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "capi_internal.hpp"
#include "contactnn/contactnn.h"
#include "core/conventions.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/plan_file.hpp"
#include "search/network_model.hpp"

using namespace contactnn;

static_assert(CONTACTNN_FACE_QUAD4 == static_cast<int>(mesh::FaceType::kQuad4));
static_assert(CONTACTNN_FACE_QUAD8 == static_cast<int>(mesh::FaceType::kQuad8));
static_assert(CONTACTNN_FACE_TRI3 == static_cast<int>(mesh::FaceType::kTri3));
static_assert(CONTACTNN_FACE_TRI6 == static_cast<int>(mesh::FaceType::kTri6));
static_assert(CONTACTNN_LOCATION_FACE == static_cast<int>(Location::kFace));
static_assert(CONTACTNN_LOCATION_EDGE == static_cast<int>(Location::kEdge));
static_assert(CONTACTNN_LOCATION_VERTEX == static_cast<int>(Location::kVertex));

namespace {
/// The check value of a live contact handle ("cnncntc" and a version byte), another than a search's.
constexpr std::uint64_t kLiveContact = 0x636e6e636e746301;
}  // namespace

/// The handle: the check value first (see contactnn_search in contactnn.cpp), then the search.
struct contactnn_contact {
  std::uint64_t check = kLiveContact;
  std::unique_ptr<contact::ContactSearch> search;
};

namespace {

bool is_live(const contactnn_contact* handle) noexcept {
  if (handle == nullptr) return false;
  std::uint64_t check = 0;
  std::memcpy(&check, static_cast<const void*>(handle), sizeof check);
  return check == kLiveContact;
}

contactnn_contact& live_handle(const char* function, contactnn_contact* handle) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, handle != nullptr, function << ": contact is NULL");
  CONTACTNN_REQUIRE_AS(InvalidArgument, is_live(handle),
                       function << ": contact is not a live handle (destroyed already, or not one that "
                                   "contactnn_contact_create wrote)");
  return *handle;
}

/// A C string option: empty for NULL; InvalidArgument naming it when longer than any path.
std::string text_option(const char* text, const char* field) {
  if (text == nullptr) return {};
  const std::string_view view(text);
  CONTACTNN_REQUIRE_AS(InvalidArgument, view.size() <= capi::kMaxPathBytes,
                       "contactnn_contact_create: options." << field << " " << quote_text(view)
                                                            << " is longer than any path ("
                                                            << capi::kMaxPathBytes << " bytes)");
  return std::string(view);
}

/// Runs `read`, its errors (of the same kind) prefixed by `context`: the option and the file.
template <class Read>
auto in_context(const std::string& context, Read&& read) {
  try {
    return read();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(context + e.what());
  } catch (const FormatError& e) {
    throw FormatError(context + e.what());
  } catch (const IoError& e) {
    throw IoError(context + e.what());
  }
}

/// The face-interior method of `options` (method and network_file, or plan_file) into `o`: the files read
/// here, once (contactnn.h: the options' contract).
void read_method(const contactnn_contact_options& options, contact::ContactSearchOptions& o) {
  constexpr const char* kFunction = "contactnn_contact_create";
  const std::string method = text_option(options.method, "method");
  const std::string network = text_option(options.network_file, "network_file");
  const std::string plan_file = text_option(options.plan_file, "plan_file");
  if (plan_file.empty()) {
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, !method.empty() || network.empty(),
        kFunction << ": options.network_file " << quote_text(network) << " is given without options.method");
    o.method = method;
    if (!network.empty()) {
      o.network = in_context(std::string(kFunction) + ": options.network_file: ",
                             [&] { return capi::load_network(network); });
    }
    return;
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, method.empty() && network.empty(),
                       kFunction << ": options.plan_file " << quote_text(plan_file)
                                 << " is given with options.method " << quote_text(method)
                                 << " and options.network_file " << quote_text(network)
                                 << "; the plan names both: give one or the other");
  const std::string context = std::string(kFunction) + ": options.plan_file: ";
  const io::ScenePlan plan = in_context(context, [&] { return io::read_plan(plan_file); });
  CONTACTNN_REQUIRE_AS(InvalidArgument, plan.surface == o.quad4,
                       kFunction << ": options.plan_file '" << plan_file << "' is a plan for "
                                 << to_string(plan.surface) << " surfaces, options.quad4_surface is "
                                 << to_string(o.quad4));
  o.method = plan.method;
  const std::filesystem::path plan_network = io::plan_network_path(plan, plan_file);
  if (plan_network.empty()) return;
  o.network = in_context(context, [&] { return capi::load_network(plan_network.string()); });
  CONTACTNN_REQUIRE_AS(FormatError, o.network->surface() == plan.surface,
                       kFunction << ": options.plan_file: '" << plan_network.string() << "' is a "
                                 << to_string(o.network->surface()) << " network, the plan '" << plan_file
                                 << "' is for " << to_string(plan.surface) << " surfaces");
}

}  // namespace

extern "C" {

int contactnn_contact_options_init(contactnn_contact_options* options) {
  return capi::guarded("contactnn_contact_options_init", [&] {
    CONTACTNN_REQUIRE_AS(InvalidArgument, options != nullptr,
                         "contactnn_contact_options_init: options is NULL");
    const contact::ContactSearchOptions d;
    *options = contactnn_contact_options{};
    options->capture_distance = d.capture_distance;
    options->quad4_surface = static_cast<int>(d.quad4);
    options->threads = d.threads;
    options->tracking = d.tracking ? 1 : 0;
    options->method = nullptr;
    options->network_file = nullptr;
    options->plan_file = nullptr;
  });
}

int contactnn_contact_create(contactnn_contact** out, size_t n_faces, const int* face_types,
                             const int* connectivity, size_t n_nodes, const int* node_ids, int id_base,
                             size_t n_slaves, const int* slave_node_ids,
                             const contactnn_contact_options* options) {
  constexpr const char* kFunction = "contactnn_contact_create";
  return capi::guarded(kFunction, [&] {
    CONTACTNN_REQUIRE_AS(InvalidArgument, out != nullptr,
                         kFunction << ": contact (where the handle goes) is NULL");
    *out = nullptr;
    CONTACTNN_REQUIRE_AS(InvalidArgument, n_faces > 0 && face_types != nullptr && connectivity != nullptr,
                         kFunction << ": n_faces = " << n_faces << ", face_types "
                                   << (face_types ? "set" : "NULL") << ", connectivity "
                                   << (connectivity ? "set" : "NULL")
                                   << "; expected at least one face and both arrays");
    CONTACTNN_REQUIRE_AS(InvalidArgument, n_nodes > 0, kFunction << ": n_nodes = 0");
    CONTACTNN_REQUIRE_AS(InvalidArgument,
                         n_faces <= (std::size_t{1} << 31) && n_nodes <= (std::size_t{1} << 31) &&
                             n_slaves <= (std::size_t{1} << 31),
                         kFunction << ": n_faces = " << n_faces << ", n_nodes = " << n_nodes
                                   << ", n_slaves = " << n_slaves << ": each at most 2^31");
    contactnn_contact_options defaults{};
    if (options == nullptr) {
      contactnn_contact_options_init(&defaults);
      options = &defaults;
    }
    CONTACTNN_REQUIRE_AS(
        InvalidArgument,
        options->quad4_surface == CONTACTNN_SURFACE_BILINEAR ||
            options->quad4_surface == CONTACTNN_SURFACE_GREGORY,
        kFunction << ": options.quad4_surface = " << options->quad4_surface
                  << ", expected CONTACTNN_SURFACE_BILINEAR (0) or CONTACTNN_SURFACE_GREGORY (1)");
    capi::require_threads(options->threads, kFunction);
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, std::isfinite(options->capture_distance),
        kFunction << ": options.capture_distance = " << options->capture_distance << " is not finite");
    std::vector<mesh::FaceType> types(n_faces);
    std::size_t total = 0;
    for (std::size_t f = 0; f < n_faces; ++f) {
      const int t = face_types[f];
      CONTACTNN_REQUIRE_AS(
          InvalidArgument, t >= CONTACTNN_FACE_QUAD4 && t <= CONTACTNN_FACE_TRI6,
          kFunction << ": face_types[" << f << "] = " << t
                    << ", expected CONTACTNN_FACE_QUAD4 (0), _QUAD8 (1), _TRI3 (2) or _TRI6 (3)");
      types[f] = static_cast<mesh::FaceType>(t);
      total += static_cast<std::size_t>(contact::face_node_count(types[f]));
    }
    const std::vector<long> conn(connectivity, connectivity + total);
    std::vector<long> ids;
    if (node_ids != nullptr) ids.assign(node_ids, node_ids + n_nodes);
    std::vector<long> slaves;
    if (slave_node_ids != nullptr) slaves.assign(slave_node_ids, slave_node_ids + n_slaves);
    contact::ContactSearchOptions o;
    o.capture_distance = options->capture_distance;
    o.quad4 = static_cast<SurfaceKind>(options->quad4_surface);
    o.threads = options->threads;
    o.tracking = options->tracking != 0;
    read_method(*options, o);
    auto handle = std::make_unique<contactnn_contact>();
    handle->search = std::make_unique<contact::ContactSearch>(
        types, conn, contact::NodeNumbering{static_cast<long>(n_nodes), id_base, ids},
        contact::SlavePoints{slaves, slave_node_ids == nullptr ? static_cast<long>(n_slaves) : 0}, o);
    *out = handle.release();
  });
}

void contactnn_contact_destroy(contactnn_contact* handle) {
  if (handle == nullptr) return;
  if (!is_live(handle)) {
    contactnn_set_last_error(
        CONTACTNN_ERROR_INVALID_ARGUMENT,
        "contactnn_contact_destroy: contact is not a live handle (destroyed already, or not one "
        "that contactnn_contact_create wrote); nothing was freed");
    return;
  }
  *static_cast<volatile std::uint64_t*>(&handle->check) = 0;
  delete handle;
}

int contactnn_contact_update(contactnn_contact* handle, size_t n_nodes, const double* coords, size_t n_slaves,
                             const double* slave_points, int* status, int* face, int* location, double* param,
                             double* point, double* gap, double* normal) {
  constexpr const char* kFunction = "contactnn_contact_update";
  return capi::guarded(kFunction, [&] {
    contact::ContactSearch& search = *live_handle(kFunction, handle).search;
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, n_nodes == static_cast<std::size_t>(search.node_count()),
        kFunction << ": n_nodes = " << n_nodes << ", the handle was created for " << search.node_count());
    const auto m = static_cast<std::size_t>(search.slave_count());
    CONTACTNN_REQUIRE_AS(InvalidArgument, n_slaves == m,
                         kFunction << ": n_slaves = " << n_slaves << ", the handle was created for " << m);
    CONTACTNN_REQUIRE_AS(InvalidArgument, coords != nullptr, kFunction << ": coords is NULL");
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, (slave_points != nullptr) == search.free_points(),
        kFunction << ": slave_points is " << (slave_points ? "set" : "NULL") << " for a search of "
                  << (search.free_points() ? "free points (their coordinates are required)"
                                           : "slave nodes (their coordinates come from coords)"));
    CONTACTNN_REQUIRE_AS(InvalidArgument, m == 0 || (status != nullptr && face != nullptr),
                         kFunction << ": status " << (status ? "set" : "NULL") << ", face "
                                   << (face ? "set" : "NULL") << "; both are required");
    const auto optional = [&](auto* p, std::size_t per) {
      using T = std::remove_pointer_t<decltype(p)>;
      return p == nullptr ? std::span<T>() : std::span<T>(p, per * m);
    };
    const contact::ContactResults out{optional(status, 1), optional(face, 1),  optional(location, 1),
                                      optional(param, 2),  optional(point, 3), optional(gap, 1),
                                      optional(normal, 3)};
    search.update(
        std::span<const double>(coords, 3 * n_nodes),
        slave_points == nullptr ? std::span<const double>() : std::span<const double>(slave_points, 3 * m),
        out);
  });
}

long contactnn_contact_slave_count(const contactnn_contact* handle) {
  return is_live(handle) ? handle->search->slave_count() : -1;
}

}  // extern "C"
