/* test_capi_contact_method: the contact search handle's face-interior method from C99 (contactnn.h:
 * contactnn_contact_options.method, .network_file, .plan_file). On a twisted bilinear quad4 face, the handle
 * with method "newton:1" answers each free point over the face's interior as contactnn_search_run does with
 * the same method on the face's raw row (local coordinates to 1e-12, location face), and not as the exact
 * search (the default); a scene plan naming that method gives the same bits; a network method with its
 * network file runs; and a bad method, a missing plan, a missing network file, a plan of the other surface
 * and a plan given with a method are refused with their documented codes and a message naming the option and
 * the file, creating nothing.
 *
 * Usage: test_capi_contact_method SOURCE_DIR WORK_DIR (data/weights of SOURCE_DIR; a plan is written under
 * WORK_DIR, which must exist). Exit status 0 when every check holds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contactnn/contactnn.h"

#define N_POINTS 24

static int failures = 0;

static void expect(int condition, const char* what) {
  if (!condition) {
    ++failures;
    fprintf(stderr, "FAILED: %s (last error: %s)\n", what, contactnn_last_error());
  }
}

/* One quad4 face, nodes 1..4: a twisted (strongly non-planar) bilinear facet. */
static const int kTypes[1] = {CONTACTNN_FACE_QUAD4};
static const int kConnectivity[4] = {1, 2, 3, 4};
static const double kCoords[12] = {0, 0, 0, 1, 0, 0.4, 1, 1, 0, 0, 1, 0.4};

typedef struct answers {
  int status[N_POINTS], face[N_POINTS], location[N_POINTS];
  double param[2 * N_POINTS], point[3 * N_POINTS], gap[N_POINTS], normal[3 * N_POINTS];
} answers;

/* Free points over the face's interior, above and below it. */
static void make_points(double* points) {
  int i;
  for (i = 0; i < N_POINTS; ++i) {
    points[3 * i] = 0.2 + 0.6 * (double)(i % 6) / 5.0;
    points[3 * i + 1] = 0.25 + 0.5 * (double)(i / 6) / 3.0;
    points[3 * i + 2] = 0.2 + (i % 2 == 0 ? 0.35 : -0.25);
  }
}

/* The handle with `options` (method fields set by the caller), updated once; 0 when it could not be made. */
static int run_handle(const contactnn_contact_options* options, const double* points, answers* a) {
  contactnn_contact* c = NULL;
  int ok = contactnn_contact_create(&c, 1, kTypes, kConnectivity, 4, NULL, 1, N_POINTS, NULL, options) ==
           CONTACTNN_SUCCESS;
  memset(a, 0, sizeof *a);
  ok = ok && contactnn_contact_update(c, 4, kCoords, N_POINTS, points, a->status, a->face, a->location,
                                      a->param, a->point, a->gap, a->normal) == CONTACTNN_SUCCESS;
  contactnn_contact_destroy(c);
  return ok;
}

static int write_text(const char* path, const char* text) {
  FILE* f = fopen(path, "w");
  if (f == NULL) return 0;
  fputs(text, f);
  return fclose(f) == 0;
}

static void write_plan(const char* path, const char* surface, const char* method, const char* network) {
  char text[1024];
  snprintf(
      text, sizeof text,
      "[plan]\nschema_version = 1\nsurface = \"%s\"\nmethod = \"%s\"\nnetwork = \"%s\"\ntarget = 0.0025\n"
      "margin = 0.8\nreached = true\n[domain]\ndeck = \"deck.inp\"\npair = 0\ndeformation = 0.1\n"
      "capture = 0.5\nnormal_tilt_tangent = 0.1\nboundary_fraction = 0.2\nheldout_count = 100\n"
      "heldout_seed = 1001\n",
      surface, method, network);
  expect(write_text(path, text), "the plan is written");
}

/* A bilinear plan naming `method` and `network`, written to `path`: its search gives `expected`, bit for bit.
 */
static void check_plan(const char* path, const char* method, const char* network, const double* points,
                       const answers* expected) {
  contactnn_contact_options options;
  answers a;
  write_plan(path, "bilinear", method, network);
  contactnn_contact_options_init(&options);
  options.plan_file = path;
  expect(run_handle(&options, points, &a), "the search with a plan");
  expect(memcmp(&a, expected, sizeof a) == 0, "the plan's search is its method's, bit for bit");
}

/* A create that must fail with `code`, a message holding `needle` (and `needle2` when not NULL), and no
 * handle.
 */
static void refused(const contactnn_contact_options* options, int code, const char* needle,
                    const char* needle2, const char* what) {
  contactnn_contact* c = (contactnn_contact*)&failures; /* overwritten with NULL by a failed create */
  const int rc = contactnn_contact_create(&c, 1, kTypes, kConnectivity, 4, NULL, 1, N_POINTS, NULL, options);
  expect(rc == code && c == NULL && strstr(contactnn_last_error(), needle) != NULL &&
             (needle2 == NULL || strstr(contactnn_last_error(), needle2) != NULL),
         what);
  if (rc == CONTACTNN_SUCCESS) contactnn_contact_destroy(c);
}

/* The handle's newton:1 answers against contactnn_search_run's on the face's raw rows. */
static void check_against_local_search(const double* points, const answers* method, const answers* exact) {
  double raw[15 * N_POINTS], param[2 * N_POINTS];
  int status[N_POINTS], i, k, compared = 0, differ = 0;
  contactnn_search* s = NULL;
  for (i = 0; i < N_POINTS; ++i) {
    for (k = 0; k < 12; ++k) raw[15 * i + k] = kCoords[k];
    for (k = 0; k < 3; ++k) raw[15 * i + 12 + k] = points[3 * i + k];
  }
  expect(contactnn_search_create(&s, CONTACTNN_SURFACE_BILINEAR, "newton:1", NULL, NULL) == CONTACTNN_SUCCESS,
         "the local search newton:1");
  expect(contactnn_search_run(s, N_POINTS, raw, param, NULL, status, NULL) == CONTACTNN_SUCCESS,
         "the local search runs");
  contactnn_search_destroy(s);
  for (i = 0; i < N_POINTS; ++i) {
    char what[160];
    expect(method->status[i] == CONTACTNN_STATUS_OK && method->face[i] == 0, "every point finds the face");
    if (status[i] != CONTACTNN_STATUS_OK) continue; /* the handle takes the exact point there */
    ++compared;
    snprintf(what, sizeof what, "point %d: handle (%.17g, %.17g) location %d, local search (%.17g, %.17g)", i,
             method->param[2 * i], method->param[2 * i + 1], method->location[i], param[2 * i],
             param[2 * i + 1]);
    expect(method->location[i] == CONTACTNN_LOCATION_FACE &&
               fabs(method->param[2 * i] - param[2 * i]) < 1e-12 &&
               fabs(method->param[2 * i + 1] - param[2 * i + 1]) < 1e-12,
           what);
    differ += fabs(method->param[2 * i] - exact->param[2 * i]) +
                  fabs(method->param[2 * i + 1] - exact->param[2 * i + 1]) >
              1e-6;
  }
  expect(compared > N_POINTS / 2, "most points over the interior are the method's");
  expect(differ > N_POINTS / 4, "newton:1 is not the exact search on the twisted face");
}

int main(int argc, char** argv) {
  double points[3 * N_POINTS];
  char plan[4200], gregory_plan[4200], network[4200], network_plan[4200];
  contactnn_contact_options options;
  answers exact, method, from_plan, net;
  if (argc != 3) {
    fprintf(stderr, "usage: test_capi_contact_method SOURCE_DIR WORK_DIR\n");
    return 2;
  }
  snprintf(plan, sizeof plan, "%s/plan.toml", argv[2]);
  snprintf(gregory_plan, sizeof gregory_plan, "%s/gregory-plan.toml", argv[2]);
  snprintf(network_plan, sizeof network_plan, "%s/network-plan.toml", argv[2]);
  snprintf(network, sizeof network, "%s/data/weights/bilinear-8.h5", argv[1]);
  make_points(points);

  expect(contactnn_contact_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
  expect(options.method == NULL && options.network_file == NULL && options.plan_file == NULL,
         "no method by default");
  expect(run_handle(&options, points, &exact), "the exact search");
  options.method = "newton:1";
  expect(run_handle(&options, points, &method), "the search with newton:1");
  check_against_local_search(points, &method, &exact);

  /* A plan naming newton:1: the same bits. */
  check_plan(plan, "newton:1", "", points, &method);

  /* A network method with its network file, and a plan naming it (an absolute path). */
  contactnn_contact_options_init(&options);
  options.method = "network+newton:1";
  options.network_file = network;
  expect(run_handle(&options, points, &net), "the search with network+newton:1");
  check_plan(network_plan, "network+newton:1", network, points, &net);

  /* Refusals. */
  contactnn_contact_options_init(&options);
  options.method = "newton:two";
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "options.method", "'newton:two'", "a bad method name");
  options.method = "start+newton:2";
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "options.method", NULL, "start+newton:K");
  options.method = "network+newton:1";
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "needs a network", NULL,
          "a network method without its file");
  options.network_file = "no-such-network.h5";
  refused(&options, CONTACTNN_ERROR_IO, "options.network_file", "no-such-network.h5",
          "a missing network file");
  contactnn_contact_options_init(&options);
  options.network_file = network;
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "without options.method", NULL,
          "a network without a method");
  contactnn_contact_options_init(&options);
  options.plan_file = "no-such-dir/plan.toml";
  refused(&options, CONTACTNN_ERROR_IO, "options.plan_file", "no-such-dir/plan.toml", "a missing plan");
  options.method = "newton:1";
  options.plan_file = plan;
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "give one or the other", NULL, "a plan and a method");
  write_plan(gregory_plan, "gregory", "newton:1", "");
  contactnn_contact_options_init(&options);
  options.plan_file = gregory_plan;
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "plan for gregory surfaces",
          "quad4_surface is bilinear", "a Gregory plan on bilinear quad4 faces");
  options.quad4_surface = CONTACTNN_SURFACE_GREGORY;
  expect(run_handle(&options, points, &from_plan), "the Gregory plan on Gregory quad4 faces");
  contactnn_contact_options_init(&options);
  options.method = "network+newton:1";
  options.network_file = network;
  options.quad4_surface = CONTACTNN_SURFACE_GREGORY;
  refused(&options, CONTACTNN_ERROR_INVALID_ARGUMENT, "bilinear network", NULL,
          "a bilinear network on Gregory quad4 faces");

  if (failures == 0) printf("PASS: the contact search handle takes a method or a plan from C\n");
  return failures == 0 ? 0 : 1;
}
