/* mpi_contact.c: the distributed contact search (contactnn/contactnn_mpi.h) under mpirun, e.g.
 *   mpirun -np 3 ./mpi_contact
 * A flat master plate z = 0 of NX x NY quad4 faces, split over the ranks by columns (rank r owns the faces of
 * the columns r * NX / P .. ), and a grid of slave nodes above it, dealt to the ranks in turn, so that most
 * slave nodes' faces belong to another rank. The slave nodes come down through the plate over the increments;
 * every rank checks its answers (the face under the node, the gap its height) and prints what it sent.
 * Exit 0 when every answer of every rank is right. */
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

#include "contactnn/contactnn_mpi.h"

#define NX 12
#define NY 4
#define SX 23 /* slave nodes per row */
#define SY 7

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  /* This rank's faces: global face id 1 + j * NX + i for the cell (i, j), its nodes 1 + j * (NX + 1) + i. */
  long face_ids[NX * NY], conn[4 * NX * NY], node_ids[(NX + 1) * (NY + 1) + SX * SY];
  int types[NX * NY];
  double coords[3 * ((NX + 1) * (NY + 1) + SX * SY)];
  size_t n_faces = 0, n_nodes = 0, n_slaves = 0;
  int has_node[(NX + 1) * (NY + 1)] = {0};
  for (int j = 0; j < NY; ++j) {
    for (int i = 0; i < NX; ++i) {
      if (i * size / NX != rank) continue;
      const long a = 1 + j * (NX + 1) + i;
      const long nodes[4] = {a, a + 1, a + NX + 2, a + NX + 1}; /* counter-clockwise seen from +z */
      face_ids[n_faces] = 1 + j * NX + i;
      types[n_faces] = CONTACTNN_FACE_QUAD4;
      for (int k = 0; k < 4; ++k) {
        conn[4 * n_faces + k] = nodes[k];
        has_node[nodes[k] - 1] = 1;
      }
      ++n_faces;
    }
  }
  for (int n = 0; n < (NX + 1) * (NY + 1); ++n) {
    if (!has_node[n]) continue;
    node_ids[n_nodes] = n + 1;
    coords[3 * n_nodes] = n % (NX + 1);
    coords[3 * n_nodes + 1] = n / (NX + 1);
    coords[3 * n_nodes + 2] = 0.0;
    ++n_nodes;
  }
  /* This rank's slave nodes (ids from 1001), every size-th of the grid. */
  long slave_ids[SX * SY];
  size_t slave_node[SX * SY];
  for (int s = rank; s < SX * SY; s += size) {
    slave_ids[n_slaves] = 1001 + s;
    slave_node[n_slaves] = n_nodes;
    node_ids[n_nodes] = 1001 + s;
    /* (k + 0.37) / 23 and / 7 of the plate: never on an edge (where SPEC 9's tie rule would pick the lower
     * id) */
    coords[3 * n_nodes] = (s % SX + 0.37) * NX / SX;
    coords[3 * n_nodes + 1] = (s / SX + 0.37) * NY / SY;
    ++n_nodes;
    ++n_slaves;
  }

  contactnn_mpi_contact* contact = NULL;
  if (contactnn_mpi_contact_create(&contact, MPI_COMM_WORLD, n_faces, face_ids, types, conn, n_nodes,
                                   node_ids, n_slaves, slave_ids, NULL) != CONTACTNN_SUCCESS) {
    fprintf(stderr, "rank %d: %s\n", rank, contactnn_last_error());
    MPI_Finalize();
    return 3;
  }
  int status[SX * SY], owner[SX * SY], location[SX * SY];
  long face[SX * SY];
  double param[2 * SX * SY], point[3 * SX * SY], gap[SX * SY], normal[3 * SX * SY];
  int wrong = 0, remote = 0;
  for (int inc = 0; inc < 4; ++inc) {
    const double height = 0.3 - 0.15 * inc; /* 0.3, 0.15, 0, -0.15: the last increment penetrates */
    for (size_t s = 0; s < n_slaves; ++s) coords[3 * slave_node[s] + 2] = height;
    if (contactnn_mpi_contact_update(contact, n_nodes, coords, n_slaves, status, face, owner, location, param,
                                     point, gap, normal) != CONTACTNN_SUCCESS) {
      fprintf(stderr, "rank %d: %s\n", rank, contactnn_last_error());
      wrong = 1;
      break;
    }
    for (size_t s = 0; s < n_slaves; ++s) {
      const double x = coords[3 * slave_node[s]], y = coords[3 * slave_node[s] + 1];
      const long expected = 1 + (long)floor(y) * NX + (long)floor(x);
      if (status[s] != CONTACTNN_STATUS_OK || face[s] != expected || fabs(gap[s] - height) > 1e-12) {
        fprintf(stderr, "rank %d increment %d slave %ld: face %ld gap %g, expected face %ld gap %g\n", rank,
                inc, slave_ids[s], face[s], gap[s], expected, height);
        wrong = 1;
      }
      remote += owner[s] != rank;
    }
    printf("rank %d increment %d: %zu slave nodes, %zu own faces, %ld bytes sent\n", rank, inc, n_slaves,
           n_faces, contactnn_mpi_contact_bytes_sent(contact));
  }
  contactnn_mpi_contact_destroy(contact);
  int any = 0;
  MPI_Allreduce(&wrong, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (rank == 0) printf("%s\n", any ? "some answers are wrong" : "every answer right");
  if (!any) printf("rank %d: %d answers on faces of other ranks\n", rank, remote);
  MPI_Finalize();
  return any ? 1 : 0;
}
