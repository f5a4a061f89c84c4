/* test_capi_contact: the contact search handle (contactnn_contact_*) from C99 on a flat surface of quad4 and
 * tri3 faces whose answers are known in closed form (a point above or below a face, beyond a boundary edge,
 * beyond a corner, out of reach), with 1-based node ids, arbitrary ids and free points; Gregory quad4; the
 * same bits at 1 and 2 threads; and every refusal: its return code, a message, and the caller's arrays
 * untouched. Exit status 0 when every check holds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contactnn/contactnn.h"

static int failures = 0;

static void expect(int condition, const char* what) {
  if (!condition) {
    ++failures;
    fprintf(stderr, "FAILED: %s (last error: %s)\n", what, contactnn_last_error());
  }
}

#define N_NODES 7
#define N_SLAVES 5
#define N_FACES 3

/* Nodes 1..6 of the surface z = 0: a (0,0) b (1,0) c (1,1) d (0,1) e (2,0) f (2,1); the quad4 a b c d and the
 * tri3 b e f and b f c. Node 7 is the moving slave node. */
static const int kTypes[N_FACES] = {CONTACTNN_FACE_QUAD4, CONTACTNN_FACE_TRI3, CONTACTNN_FACE_TRI3};
static const int kConnectivity[10] = {1, 2, 3, 4, 2, 5, 6, 2, 6, 3};

/* The slave points and what each must get: face, location, gap, point, normal. */
static const double kSlaves[N_SLAVES][3] = {
    {0.25, 0.5, 0.2}, {1.8, 0.3, -0.1}, {2.3, 0.5, 0.4}, {-0.3, -0.4, 0.0}, {10.0, 10.0, 10.0}};
static const int kFace[N_SLAVES] = {0, 1, 1, 0, -1};
static const int kLocation[N_SLAVES] = {CONTACTNN_LOCATION_FACE, CONTACTNN_LOCATION_FACE,
                                        CONTACTNN_LOCATION_EDGE, CONTACTNN_LOCATION_VERTEX, -1};
static const double kGap[N_SLAVES] = {0.2, -0.1, 0.5, 0.5, 0.0};
static const double kPoint[N_SLAVES][3] = {{0.25, 0.5, 0}, {1.8, 0.3, 0}, {2, 0.5, 0}, {0, 0, 0}, {0, 0, 0}};
static const double kNormal[N_SLAVES][3] = {{0, 0, 1}, {0, 0, 1}, {0.6, 0, 0.8}, {-0.6, -0.8, 0}, {0, 0, 0}};

typedef struct answers {
  int status[N_SLAVES], face[N_SLAVES], location[N_SLAVES];
  double param[2 * N_SLAVES], point[3 * N_SLAVES], gap[N_SLAVES], normal[3 * N_SLAVES];
} answers;

static void fill(answers* a) {
  int i;
  memset(a, 0, sizeof *a); /* the padding too: the structs are compared by memcmp */
  for (i = 0; i < N_SLAVES; ++i) a->status[i] = a->face[i] = a->location[i] = -99;
  for (i = 0; i < 2 * N_SLAVES; ++i) a->param[i] = -99.0;
  for (i = 0; i < 3 * N_SLAVES; ++i) a->point[i] = a->normal[i] = -99.0;
  for (i = 0; i < N_SLAVES; ++i) a->gap[i] = -99.0;
}

static int untouched(const answers* a) {
  answers sentinel;
  fill(&sentinel);
  return memcmp(a, &sentinel, sizeof sentinel) == 0;
}

static int update(contactnn_contact* c, const double* coords, const double* free_points, answers* a) {
  return contactnn_contact_update(c, N_NODES, coords, N_SLAVES, free_points, a->status, a->face, a->location,
                                  a->param, a->point, a->gap, a->normal);
}

static void check_answers(const answers* a, const char* what) {
  char line[200];
  int i, k;
  for (i = 0; i < N_SLAVES; ++i) {
    int ok = a->status[i] == (kFace[i] < 0 ? CONTACTNN_STATUS_NO_SEGMENT : CONTACTNN_STATUS_OK) &&
             a->face[i] == kFace[i] && a->location[i] == kLocation[i] && fabs(a->gap[i] - kGap[i]) < 1e-12;
    for (k = 0; k < 3; ++k) {
      ok = ok && fabs(a->point[3 * i + k] - kPoint[i][k]) < 1e-12 &&
           fabs(a->normal[3 * i + k] - kNormal[i][k]) < 1e-12;
    }
    snprintf(line, sizeof line, "%s: slave %d (status %d face %d location %d gap %g)", what, i, a->status[i],
             a->face[i], a->location[i], a->gap[i]);
    expect(ok, line);
  }
}

/* A handle of the plate's faces and free points made with `options`, updated once: "create NAME" must
 * succeed, "update NAME" too, and the answers are check_answers'. Returns the handle (NULL: create failed).
 */
static contactnn_contact* create_and_check(const contactnn_contact_options* options, const double* coords,
                                           const double* free_points, answers* a, const char* name) {
  contactnn_contact* c = NULL;
  char what[96];
  snprintf(what, sizeof what, "create %s", name);
  expect(contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL,
                                  options) == CONTACTNN_SUCCESS,
         what);
  fill(a);
  snprintf(what, sizeof what, "update %s", name);
  expect(update(c, coords, free_points, a) == CONTACTNN_SUCCESS, what);
  check_answers(a, name);
  return c;
}

int main(void) {
  /* Node 7 (the first slave node) at kSlaves[0]; the others are free points or nodes below. */
  double coords[3 * N_NODES] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0, 0, 0, 0};
  double free_points[3 * N_SLAVES];
  double coords_all[3 * (N_NODES + N_SLAVES)];
  int i, k, rc;
  contactnn_contact* c = NULL;
  contactnn_contact_options options;
  answers a, b;

  expect(contactnn_contact_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
  expect(options.capture_distance == 0.0 && options.quad4_surface == CONTACTNN_SURFACE_BILINEAR &&
             options.threads == 0 && options.tracking == 1,
         "the default options");
  for (i = 0; i < N_SLAVES; ++i) {
    for (k = 0; k < 3; ++k) free_points[3 * i + k] = kSlaves[i][k];
  }

  /* Free points, 1-based ids. */
  options.capture_distance = 2.0;
  rc = contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL,
                                &options);
  expect(rc == CONTACTNN_SUCCESS && c != NULL, "create with free points");
  expect(contactnn_contact_slave_count(c) == N_SLAVES, "slave count");
  fill(&a);
  expect(update(c, coords, free_points, &a) == CONTACTNN_SUCCESS, "update with free points");
  check_answers(&a, "free points");
  expect(fabs(a.param[0] + 0.5) < 1e-12 && fabs(a.param[1]) < 1e-12, "the quad4's (xi, eta)");
  expect(fabs(a.param[2] - 0.5) < 1e-12 && fabs(a.param[3] - 0.3) < 1e-12, "the tri3's (r, s)");
  /* Increments: the surface lifted by 1 and the points with it: the same gaps. */
  for (i = 0; i < N_NODES; ++i) coords[3 * i + 2] += 1.0;
  for (i = 0; i < N_SLAVES; ++i) free_points[3 * i + 2] += 1.0;
  fill(&b);
  expect(update(c, coords, free_points, &b) == CONTACTNN_SUCCESS, "second update");
  for (i = 0; i < N_SLAVES; ++i)
    expect(b.face[i] == a.face[i] && fabs(b.gap[i] - a.gap[i]) < 1e-12, "lifted");
  for (i = 0; i < N_NODES; ++i) coords[3 * i + 2] -= 1.0;
  for (i = 0; i < N_SLAVES; ++i) free_points[3 * i + 2] -= 1.0;

  /* Refusals of an update: the code, a message, nothing written, the handle still usable. */
  fill(&a);
  rc = contactnn_contact_update(c, N_NODES - 1, coords, N_SLAVES, free_points, a.status, a.face, a.location,
                                a.param, a.point, a.gap, a.normal);
  expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "n_nodes") && untouched(&a),
         "n_nodes mismatch refused");
  rc = contactnn_contact_update(c, N_NODES, coords, N_SLAVES + 1, free_points, a.status, a.face, a.location,
                                a.param, a.point, a.gap, a.normal);
  expect(
      rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "n_slaves") && untouched(&a),
      "n_slaves mismatch refused");
  rc = update(c, coords, NULL, &a);
  expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "slave_points") &&
             untouched(&a),
         "free points missing refused");
  rc = contactnn_contact_update(c, N_NODES, coords, N_SLAVES, free_points, NULL, a.face, NULL, NULL, NULL,
                                NULL, NULL);
  expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && untouched(&a), "NULL status refused");
  coords[3 * 2 + 1] = NAN;
  rc = update(c, coords, free_points, &a);
  expect(rc == CONTACTNN_ERROR_NUMERICAL && strstr(contactnn_last_error(), "node 3") && untouched(&a),
         "a NaN coordinate of face node 3 refused");
  coords[3 * 2 + 1] = 1.0;
  free_points[4] = INFINITY;
  rc = update(c, coords, free_points, &a);
  expect(rc == CONTACTNN_ERROR_NUMERICAL && strstr(contactnn_last_error(), "free point 1") && untouched(&a),
         "an infinite free point refused");
  free_points[4] = kSlaves[1][1];
  expect(update(c, coords, free_points, &a) == CONTACTNN_SUCCESS, "an update after the refusals");
  check_answers(&a, "after the refusals");
  contactnn_contact_destroy(c);
  rc = update(c, coords, free_points, &b);
  expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "not a live handle"),
         "a destroyed handle refused");
  contactnn_contact_destroy(c);
  expect(strstr(contactnn_last_error(), "nothing was freed") != NULL, "destroying twice frees nothing");
  expect(contactnn_contact_slave_count(c) == -1, "no slave count of a dead handle");

  /* Slave nodes by arbitrary ids: the surface's nodes 101..106, the slave nodes 201..205 placed at the
   * points. */
  {
    int ids[N_NODES - 1 + N_SLAVES], slaves[N_SLAVES], conn[10];
    for (i = 0; i < N_NODES - 1; ++i) ids[i] = 101 + i;
    for (i = 0; i < N_SLAVES; ++i) ids[N_NODES - 1 + i] = slaves[i] = 205 - i;
    for (i = 0; i < 10; ++i) conn[i] = kConnectivity[i] + 100;
    memcpy(coords_all, coords, sizeof(double) * 3 * (N_NODES - 1));
    for (i = 0; i < N_SLAVES; ++i) {
      for (k = 0; k < 3; ++k) coords_all[3 * (N_NODES - 1 + i) + k] = kSlaves[i][k];
    }
    for (i = 0; i < 2; ++i) {
      contactnn_contact* t = NULL;
      options.threads = i + 1;
      rc = contactnn_contact_create(&t, N_FACES, kTypes, conn, N_NODES - 1 + N_SLAVES, ids, 0, N_SLAVES,
                                    slaves, &options);
      expect(rc == CONTACTNN_SUCCESS, "create with arbitrary ids");
      fill(i == 0 ? &a : &b);
      rc = contactnn_contact_update(
          t, N_NODES - 1 + N_SLAVES, coords_all, N_SLAVES, NULL, (i == 0 ? &a : &b)->status,
          (i == 0 ? &a : &b)->face, (i == 0 ? &a : &b)->location, (i == 0 ? &a : &b)->param,
          (i == 0 ? &a : &b)->point, (i == 0 ? &a : &b)->gap, (i == 0 ? &a : &b)->normal);
      expect(rc == CONTACTNN_SUCCESS, "update of slave nodes");
      contactnn_contact_destroy(t);
    }
    /* Slave node 205 - i is at kSlaves[i]: the answers in the order of slave_node_ids (205, 204, ...) are
     * those of kSlaves (slaves[i] = 205 - i). */
    check_answers(&a, "slave nodes, arbitrary ids, 1 thread");
    expect(memcmp(&a, &b, sizeof a) == 0, "the same bits at 1 and 2 threads");
  }

  /* Every update a fresh search, on OpenMP's default team (ctest runs this program a second time with
   * OMP_NUM_THREADS=100000, which libgomp cannot start: the handle caps it at CONTACTNN_MAX_THREADS). */
  options.threads = 0;
  options.tracking = 0;
  c = create_and_check(&options, coords, free_points, &a, "without tracking");
  contactnn_contact_destroy(c);
  options.tracking = 1;

  /* Gregory quad4: the flat plate's patch (node normals +z) gives the same point, (u, v) in [0, 1]^2. */
  options.threads = 0;
  options.quad4_surface = CONTACTNN_SURFACE_GREGORY;
  c = create_and_check(&options, coords, free_points, &a, "Gregory");
  expect(fabs(a.param[0] - 0.25) < 1e-10 && fabs(a.param[1] - 0.5) < 1e-10, "the Gregory quad4's (u, v)");
  contactnn_contact_destroy(c);

  /* Refusals at creation: the code, a message naming the culprit, no handle. */
  {
    int bad_types[N_FACES] = {CONTACTNN_FACE_QUAD4, 7, CONTACTNN_FACE_TRI3};
    int bad_conn[10];
    int slave_zero = 0;
    contactnn_contact_options bad;
    memcpy(bad_conn, kConnectivity, sizeof bad_conn);
    bad_conn[5] = 99;
    c = (contactnn_contact*)&rc; /* overwritten with NULL by every failed create */
    rc = contactnn_contact_create(&c, N_FACES, bad_types, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL,
                                  NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && c == NULL &&
               strstr(contactnn_last_error(), "face_types[1] = 7"),
           "an unknown face type refused");
    rc = contactnn_contact_create(&c, N_FACES, kTypes, bad_conn, N_NODES, NULL, 1, N_SLAVES, NULL, NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && c == NULL && strstr(contactnn_last_error(), "node 99"),
           "a face naming a node that does not exist refused");
    rc = contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES - 1, NULL, 0, N_SLAVES, NULL,
                                  NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "names node 6"),
           "1-based connectivity read 0-based refused (node 6 of 0..5)");
    rc = contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, 1, &slave_zero, NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "slave node"),
           "a slave node that does not exist refused");
    rc = contactnn_contact_create(&c, 0, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL, NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT, "no faces refused");
    rc = contactnn_contact_create(NULL, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL,
                                  NULL);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT, "NULL contact refused");
    contactnn_contact_options_init(&bad);
    bad.quad4_surface = 3;
    rc = contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL, &bad);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "quad4_surface"),
           "an unknown quad4 surface refused");
    contactnn_contact_options_init(&bad);
    bad.threads = CONTACTNN_MAX_THREADS + 1;
    rc = contactnn_contact_create(&c, N_FACES, kTypes, kConnectivity, N_NODES, NULL, 1, N_SLAVES, NULL, &bad);
    expect(rc == CONTACTNN_ERROR_INVALID_ARGUMENT && strstr(contactnn_last_error(), "threads"),
           "too many threads refused");
  }

  if (failures == 0) printf("PASS: the contact search handle from C\n");
  return failures == 0 ? 0 : 1;
}
