// The C interface of the distributed contact search (contactnn/contactnn_mpi.h) over
// mpi::DistributedContactSearch. Errors become return codes and contactnn_last_error's message
// (lib/capi/capi_internal.hpp's guarded); the C++ class already makes every rank agree on them.
#include "contactnn/contactnn_mpi.h"

#include <memory>
#include <span>
#include <vector>

#include "capi_internal.hpp"
#include "mpi/distributed_contact_search.hpp"

struct contactnn_mpi_contact {
  std::unique_ptr<contactnn::mpi::DistributedContactSearch> search;
  std::size_t nodes = 0;
  std::size_t slaves = 0;
};

namespace {

/// A caller's array as a span: empty where it is NULL (the C++ class then reports the size on every rank).
template <class T>
std::span<T> array(T* p, std::size_t n) {
  return p == nullptr ? std::span<T>() : std::span<T>(p, n);
}

}  // namespace

extern "C" {

int contactnn_mpi_contact_create(contactnn_mpi_contact** contact, MPI_Comm comm, size_t n_faces,
                                 const long* face_ids, const int* face_types, const long* connectivity,
                                 size_t n_nodes, const long* node_ids, size_t n_slaves,
                                 const long* slave_node_ids, const contactnn_contact_options* options) {
  return contactnn::capi::guarded("contactnn_mpi_contact_create", [&] {
    CONTACTNN_REQUIRE_AS(contactnn::InvalidArgument, contact != nullptr,
                         "contactnn_mpi_contact_create: contact is NULL");
    *contact = nullptr;
    contactnn::contact::ContactSearchOptions o;
    if (options != nullptr) {
      o.capture_distance = options->capture_distance;
      o.quad4 = options->quad4_surface == CONTACTNN_SURFACE_BILINEAR ? contactnn::SurfaceKind::kBilinear
                                                                     : contactnn::SurfaceKind::kGregory;
      o.threads = options->threads;
      o.tracking = options->tracking != 0;
      const auto given = [](const char* text) { return text != nullptr && text[0] != '\0'; };
      CONTACTNN_REQUIRE_AS(
          contactnn::InvalidArgument,
          !given(options->method) && !given(options->network_file) && !given(options->plan_file),
          "contactnn_mpi_contact_create: options.method, .network_file and .plan_file must be "
          "NULL or empty: the distributed search runs the exact search only");
    }
    // A face type that is none of CONTACTNN_FACE_* becomes one the C++ class refuses (on every rank).
    std::vector<contactnn::mesh::FaceType> types;
    if (face_types != nullptr) {
      for (std::size_t f = 0; f < n_faces; ++f) {
        const int t = face_types[f];
        types.push_back(static_cast<contactnn::mesh::FaceType>(t >= 0 && t <= 3 ? t : 255));
      }
    }
    std::size_t total = 0;
    for (const auto t : types)
      total += static_cast<std::size_t>(std::max(contactnn::contact::face_node_count(t), 0));
    auto handle = std::make_unique<contactnn_mpi_contact>();
    handle->nodes = n_nodes;
    handle->slaves = n_slaves;
    handle->search = std::make_unique<contactnn::mpi::DistributedContactSearch>(
        comm, array(face_ids, n_faces), types, array(connectivity, total), array(node_ids, n_nodes),
        array(slave_node_ids, n_slaves), o);
    *contact = handle.release();
  });
}

int contactnn_mpi_contact_create_f(contactnn_mpi_contact** contact, MPI_Fint comm, size_t n_faces,
                                   const long* face_ids, const int* face_types, const long* connectivity,
                                   size_t n_nodes, const long* node_ids, size_t n_slaves,
                                   const long* slave_node_ids, const contactnn_contact_options* options) {
  return contactnn_mpi_contact_create(contact, MPI_Comm_f2c(comm), n_faces, face_ids, face_types,
                                      connectivity, n_nodes, node_ids, n_slaves, slave_node_ids, options);
}

int contactnn_mpi_contact_update(contactnn_mpi_contact* contact, size_t n_nodes, const double* coords,
                                 size_t n_slaves, int* status, long* face, int* owner, int* location,
                                 double* param, double* point, double* gap, double* normal) {
  return contactnn::capi::guarded("contactnn_mpi_contact_update", [&] {
    CONTACTNN_REQUIRE_AS(contactnn::InvalidArgument, contact != nullptr,
                         "contactnn_mpi_contact_update: contact is NULL");
    // A count that is not the handle's: arrays the C++ class finds of the wrong size, on every rank.
    const std::size_t n = n_nodes == contact->nodes ? n_nodes : 0;
    const std::size_t m = n_slaves == contact->slaves ? n_slaves : 0;
    contact->search->update(array(coords, 3 * n),
                            {array(status, m), array(face, m), array(owner, m), array(location, m),
                             array(param, 2 * m), array(point, 3 * m), array(gap, m), array(normal, 3 * m)});
  });
}

void contactnn_mpi_contact_destroy(contactnn_mpi_contact* contact) { delete contact; }

int contactnn_mpi_contact_counts(const contactnn_mpi_contact* contact, contactnn_mpi_counts* counts) {
  return contactnn::capi::guarded("contactnn_mpi_contact_counts", [&] {
    CONTACTNN_REQUIRE_AS(contactnn::InvalidArgument, contact != nullptr && counts != nullptr,
                         "contactnn_mpi_contact_counts: contact or counts is NULL");
    const contactnn::mpi::ExchangeCounts& c = contact->search->counts();
    *counts = {c.bytes_sent,     c.header_bytes_sent, c.messages_sent,        c.collectives,
               c.allreduces,     c.ghost_faces_sent,  c.ghost_faces_received, c.ghost_nodes_received,
               c.faces_searched, c.exchanged};
  });
}

long contactnn_mpi_contact_bytes_sent(const contactnn_mpi_contact* contact) {
  return contact == nullptr ? -1 : contact->search->counts().bytes_sent;
}

}  // extern "C"
