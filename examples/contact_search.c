/* contact_search.c: the contact search handle of contactnn from C, as an FE code calls it.
 *
 * A plate [0, 4] x [0, 4] x [-1, 0] of 4 x 4 cells (the left half hexahedra, C3D8, whose top faces are quad4;
 * the right half wedges, C3D6, two per cell, whose top faces are tri3) is the master body; a faceted
 * spherical cap (61 nodes on rings of a sphere of radius 3) is the slave body. Over ten increments the cap
 * moves down into the plate and slides sideways while the plate sags; each increment passes the node
 * coordinates to the handle and prints every slave node in contact: its face, where on the face (face, edge,
 * vertex), the signed gap (< 0: penetration), the closest point and the unit normal.
 *
 * Build against the installed package (examples/CMakeLists.txt) and run: ./contact_search_c [DIR]. With DIR
 * the program also writes each increment's mesh as a CalculiX deck DIR/incNN.inp (the same nodes, elements,
 * slave node surface and contact pair), which `gen-configs --scene DIR/incNN.inp` searches; tests/examples
 * checks that both agree. */
#include <contactnn/contactnn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define CELLS 4                       /* cells per side of the plate */
#define GRID (CELLS + 1)              /* nodes per side */
#define PLATE_NODES (2 * GRID * GRID) /* top layer (ids 1..25), bottom layer (26..50) */
#define RINGS 4                       /* the cap: a pole and rings of 6, 12, 18, 24 nodes */
#define CAP_NODES (1 + 3 * RINGS * (RINGS + 1))
#define N_NODES (PLATE_NODES + CAP_NODES) /* node ids 1..N_NODES, 1-based */
#define MAX_FACES (2 * CELLS * CELLS)
#define INCREMENTS 10

static const double kPi = 3.14159265358979323846;

static int top(int i, int j) { return 1 + i + GRID * j; }

/* The faces, in the order of the elements that own them (element e has face e - 1): their types and node ids.
 */
static int build_faces(int* types, int* connectivity) {
  int n = 0, at = 0, i, j;
  for (j = 0; j < CELLS; ++j) {
    for (i = 0; i < CELLS; ++i) {
      const int a = top(i, j), b = top(i + 1, j), c = top(i + 1, j + 1), d = top(i, j + 1);
      if (i < CELLS / 2) { /* a hexahedron: one quad4, counter-clockwise seen from above (outward) */
        types[n++] = CONTACTNN_FACE_QUAD4;
        connectivity[at++] = a, connectivity[at++] = b, connectivity[at++] = c, connectivity[at++] = d;
      } else { /* two wedges: two tri3 */
        types[n++] = CONTACTNN_FACE_TRI3;
        connectivity[at++] = a, connectivity[at++] = b, connectivity[at++] = c;
        types[n++] = CONTACTNN_FACE_TRI3;
        connectivity[at++] = a, connectivity[at++] = c, connectivity[at++] = d;
      }
    }
  }
  return n;
}

/* The node coordinates at increment k (0: the start). */
static void place_nodes(int k, double* x) {
  const double radius = 3.0;
  const double centre[3] = {1.7 + 0.06 * k, 1.9 + 0.03 * k, radius + 0.05 - 0.02 * k};
  int i, j, r, q, n = 0;
  for (j = 0; j < GRID; ++j) {
    for (i = 0; i < GRID; ++i, ++n) { /* the top, sagging by up to 0.002 k in the middle */
      x[3 * n] = i, x[3 * n + 1] = j;
      x[3 * n + 2] = -0.002 * k * sin(kPi * i / CELLS) * sin(kPi * j / CELLS);
    }
  }
  for (j = 0; j < GRID; ++j) {
    for (i = 0; i < GRID; ++i, ++n) x[3 * n] = i, x[3 * n + 1] = j, x[3 * n + 2] = -1.0;
  }
  for (r = 0; r <= RINGS; ++r) {
    const double polar = r * 8.0 * kPi / 180.0;
    const int count = r == 0 ? 1 : 6 * r;
    for (q = 0; q < count; ++q, ++n) {
      const double azimuth = 2.0 * kPi * q / count;
      x[3 * n] = centre[0] + radius * sin(polar) * cos(azimuth);
      x[3 * n + 1] = centre[1] + radius * sin(polar) * sin(azimuth);
      x[3 * n + 2] = centre[2] - radius * cos(polar);
    }
  }
}

/* The mesh of increment k as a deck: the plate's elements, its top as the master surface, the cap's nodes as
 * a node surface, one contact pair. */
static int write_deck(const char* dir, int k, const double* x) {
  char path[4096];
  FILE* f;
  int n, i, j, e = 0;
  snprintf(path, sizeof path, "%s/inc%02d.inp", dir, k);
  f = fopen(path, "w");
  if (f == NULL) return 1;
  fprintf(f, "** contact_search.c, increment %d\n*NODE\n", k);
  for (n = 0; n < N_NODES; ++n)
    fprintf(f, "%d, %.17g, %.17g, %.17g\n", n + 1, x[3 * n], x[3 * n + 1], x[3 * n + 2]);
  for (j = 0; j < CELLS; ++j) {
    for (i = 0; i < CELLS; ++i) {
      const int a = top(i, j), b = top(i + 1, j), c = top(i + 1, j + 1), d = top(i, j + 1),
                below = GRID * GRID;
      if (i < CELLS / 2) {
        fprintf(f, "*ELEMENT, TYPE=C3D8, ELSET=EPLATE\n%d, %d, %d, %d, %d, %d, %d, %d, %d\n", ++e, a + below,
                b + below, c + below, d + below, a, b, c, d);
      } else {
        fprintf(f, "*ELEMENT, TYPE=C3D6, ELSET=EPLATE\n%d, %d, %d, %d, %d, %d, %d\n", ++e, a + below,
                b + below, c + below, a, b, c);
        fprintf(f, "%d, %d, %d, %d, %d, %d, %d\n", ++e, a + below, c + below, d + below, a, c, d);
      }
    }
  }
  fprintf(f, "*NSET, NSET=NCAP, GENERATE\n%d, %d, 1\n", PLATE_NODES + 1, N_NODES);
  fprintf(f, "*SURFACE, NAME=SPLATE, TYPE=ELEMENT\nEPLATE, S2\n*SURFACE, NAME=SCAP, TYPE=NODE\nNCAP\n");
  fprintf(f, "*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE\nSCAP, SPLATE\n");
  return fclose(f) != 0;
}

int main(int argc, char** argv) {
  static const char* kLocation[] = {"face", "edge", "vertex"};
  int types[MAX_FACES], connectivity[4 * MAX_FACES], slaves[CAP_NODES];
  int status[CAP_NODES], face[CAP_NODES], location[CAP_NODES];
  double x[3 * N_NODES], param[2 * CAP_NODES], point[3 * CAP_NODES], gap[CAP_NODES], normal[3 * CAP_NODES];
  contactnn_contact* contact = NULL;
  int n_faces, k, i;

  n_faces = build_faces(types, connectivity);
  for (i = 0; i < CAP_NODES; ++i) slaves[i] = PLATE_NODES + 1 + i;
  /* Node ids from 1 (id_base 1), the slave points are nodes, the default options (NULL): capture within one
   * largest face size, bilinear quad4, tracking. */
  if (contactnn_contact_create(&contact, n_faces, types, connectivity, N_NODES, NULL, 1, CAP_NODES, slaves,
                               NULL) != CONTACTNN_SUCCESS) {
    fprintf(stderr, "contactnn_contact_create: %s\n", contactnn_last_error());
    return 1;
  }
  printf("# increment node face face_type location gap px py pz nx ny nz  (faces from 1, as the elements)\n");
  for (k = 0; k <= INCREMENTS; ++k) {
    int contacts = 0;
    place_nodes(k, x);
    if (argc > 1 && write_deck(argv[1], k, x) != 0) {
      fprintf(stderr, "cannot write %s/inc%02d.inp\n", argv[1], k);
      return 4;
    }
    if (contactnn_contact_update(contact, N_NODES, x, CAP_NODES, NULL, status, face, location, param, point,
                                 gap, normal) != CONTACTNN_SUCCESS) {
      fprintf(stderr, "contactnn_contact_update: %s\n", contactnn_last_error());
      return 1;
    }
    for (i = 0; i < CAP_NODES; ++i) contacts += status[i] == CONTACTNN_STATUS_OK;
    printf("# increment %d: %d of %d slave nodes within reach\n", k, contacts, CAP_NODES);
    for (i = 0; i < CAP_NODES; ++i) {
      if (status[i] != CONTACTNN_STATUS_OK) continue;
      printf("%d %d %d %s %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", k, slaves[i], face[i] + 1,
             types[face[i]] == CONTACTNN_FACE_QUAD4 ? "quad4" : "tri3", kLocation[location[i]], gap[i],
             point[3 * i], point[3 * i + 1], point[3 * i + 2], normal[3 * i], normal[3 * i + 1],
             normal[3 * i + 2]);
    }
  }
  contactnn_contact_destroy(contact);
  return 0;
}
