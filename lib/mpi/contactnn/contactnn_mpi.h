/* contactnn_mpi.h: the contact search across MPI ranks (issue 41; C++: mpi/distributed_contact_search.hpp),
 * for finite-element codes whose mesh is split over MPI ranks. Built only where contactnn's build found MPI;
 * link contactnn::mpi_c (libcontactnn_mpi_c), which needs libcontactnn_c (contactnn.h: return codes, options,
 * contactnn_last_error) and the program's MPI.
 *
 * Each rank passes its own master faces (global face ids, types, connectivity in global node ids), the global
 * ids and coordinates of at least the nodes of its faces and of its slave nodes, and its own slave nodes
 * (global ids). For each of its slave nodes a rank gets the closest point over the master faces of ALL ranks:
 * the answer of the serial contactnn_contact_update over every face given in increasing global face id (the
 * same bits), whatever the rank count and the split; `face` is the global face id and `owner` the rank that
 * passed it.
 *
 * Every function but contactnn_mpi_contact_slave_count is collective over the communicator given at creation
 * (the library works on a duplicate of it and never calls MPI_Init: the program initialises MPI first and
 * finalises it after destroying the handle). Bad input on any rank (a face or node id given twice, two ranks
 * giving different coordinates for one node id, a face naming a node its rank does not pass, a non-finite
 * coordinate, a count or array that does not fit) returns the same code and message on every rank, and
 * nothing is written on any rank. Only a NULL `contact` answers on its own rank alone (a programming error:
 * the other ranks then wait in the collective).
 *
 * Options: contactnn_contact_options; quad4_surface must be bilinear (Gregory: INVALID_ARGUMENT), `tracking`
 * keeps the ghost layer (the faces exchanged between ranks) until the movement budget is spent (0: exchanged
 * at every update; the answers are the same), `threads` the local search's; `method`, `network_file` and
 * `plan_file` NULL or empty (the exact search only; a face-interior method is INVALID_ARGUMENT).
 *
 * Sample use (error handling shortened):
 *   MPI_Init(&argc, &argv);
 *   contactnn_mpi_contact* c = NULL;
 *   contactnn_mpi_contact_create(&c, MPI_COMM_WORLD, n_faces, face_ids, types, conn, n_nodes, node_ids,
 * n_slaves, slave_ids, NULL); for (int inc = 0; inc < n_inc; ++inc) contactnn_mpi_contact_update(c, n_nodes,
 * coords, n_slaves, status, face, owner, location, param, point, gap, normal);
 *   contactnn_mpi_contact_destroy(c);
 *   MPI_Finalize();
 */
#ifndef CONTACTNN_CONTACTNN_MPI_H
#define CONTACTNN_CONTACTNN_MPI_H

#include <mpi.h>
#include <stddef.h>

#include "contactnn/contactnn.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opaque handle of a distributed contact search. */
typedef struct contactnn_mpi_contact contactnn_mpi_contact;

/* Collective. Creates a distributed contact search on a duplicate of `comm`: this rank's n_faces faces
 * (face_ids, face_types CONTACTNN_FACE_*, connectivity 4, 8, 3 or 6 global node ids per face), the global ids
 * of the n_nodes nodes of the coordinate arrays the updates pass, this rank's n_slaves slave node ids
 * (options NULL: the defaults). A rank may pass no faces, no slave nodes, or neither (NULL arrays with a
 * count of 0). */
CONTACTNN_API int contactnn_mpi_contact_create(contactnn_mpi_contact** contact, MPI_Comm comm, size_t n_faces,
                                               const long* face_ids, const int* face_types,
                                               const long* connectivity, size_t n_nodes, const long* node_ids,
                                               size_t n_slaves, const long* slave_node_ids,
                                               const contactnn_contact_options* options);

/* As contactnn_mpi_contact_create, the communicator a Fortran handle (an INTEGER, converted by MPI_Comm_f2c):
 * what the Fortran module (contactnn_mpi.f90) calls. */
CONTACTNN_API int contactnn_mpi_contact_create_f(contactnn_mpi_contact** contact, MPI_Fint comm,
                                                 size_t n_faces, const long* face_ids, const int* face_types,
                                                 const long* connectivity, size_t n_nodes,
                                                 const long* node_ids, size_t n_slaves,
                                                 const long* slave_node_ids,
                                                 const contactnn_contact_options* options);

/* Collective. One increment: coords holds n_nodes x 3 values in the order of node_ids. Writes, per slave node
 * i: status[i], face[i] (global face id, -1 when none) and, where not NULL, owner[i] (the rank that passed
 * the face, -1 when none), location, param (2 per node), point (3), gap and normal (3), as
 * contactnn_contact_update. */
CONTACTNN_API int contactnn_mpi_contact_update(contactnn_mpi_contact* contact, size_t n_nodes,
                                               const double* coords, size_t n_slaves, int* status, long* face,
                                               int* owner, int* location, double* param, double* point,
                                               double* gap, double* normal);

/* Collective (frees the duplicate communicator). NULL does nothing. */
CONTACTNN_API void contactnn_mpi_contact_destroy(contactnn_mpi_contact* contact);

/* What this rank sent in the last update (before the first update: at creation). Bytes are the payloads of
 * its all-to-all messages to other ranks and of the allgather of slave boxes (once per other rank); the
 * message sizes sent before each all-to-all are counted apart. */
typedef struct contactnn_mpi_counts {
  long bytes_sent;
  long header_bytes_sent;    /* the message sizes each all-to-all sends first (4 bytes per other rank) */
  long messages_sent;        /* non-empty payloads to other ranks */
  long collectives;          /* collective calls (all-to-all, allgather, allreduce, bcast) */
  long allreduces;           /* of which MPI_Allreduce */
  long ghost_faces_sent;     /* faces of this rank sent to other ranks */
  long ghost_faces_received; /* faces of other ranks this rank searched */
  long ghost_nodes_received; /* node coordinates received for them, per update */
  long faces_searched;       /* own faces within reach plus the ghost faces */
  long exchanged;            /* 1 where the update chose the ghost faces afresh, 0 where it kept them */
} contactnn_mpi_counts;

/* Local. Fills *counts with the last update's counts; INVALID_ARGUMENT for NULL arguments. */
CONTACTNN_API int contactnn_mpi_contact_counts(const contactnn_mpi_contact* contact,
                                               contactnn_mpi_counts* counts);

/* The bytes this rank sent in the last update (contactnn_mpi_counts's bytes_sent), -1 for NULL. Local. */
CONTACTNN_API long contactnn_mpi_contact_bytes_sent(const contactnn_mpi_contact* contact);

#ifdef __cplusplus
}
#endif

#endif /* CONTACTNN_CONTACTNN_MPI_H */
