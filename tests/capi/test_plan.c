/* test_plan: a scene plan (scene-study's plan.toml, SPEC 7) loaded through the C interface, from C99.
 * contactnn_search_create_from_plan gives the search the plan names, bit for bit the one
 * contactnn_search_create makes from the same surface, method and network file (the network found relative to
 * the plan's directory, not the working directory); a malformed plan, a missing one and a plan whose network
 * is missing fail with their documented codes and a message naming the file, the line and the key, and write
 * no handle.
 *
 * Usage: test_capi_plan SOURCE_DIR WORK_DIR   (data/weights of SOURCE_DIR; the plans are written under
 * WORK_DIR, which must exist). Exit status 0 when every check holds; each failed check is printed. */
#include <contactnn/contactnn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refusal_check.h"

#define QUERIES 40

/* Writes `text` to `path`; 0 on failure. */
static int write_text(const char* path, const char* text) {
  FILE* f = fopen(path, "w");
  if (f == NULL) return 0;
  fputs(text, f);
  return fclose(f) == 0;
}

/* Copies a file byte for byte; 0 on failure. */
static int copy_file(const char* from, const char* to) {
  char buffer[65536];
  size_t n;
  FILE* in = fopen(from, "rb");
  FILE* out = fopen(to, "wb");
  int ok = in != NULL && out != NULL;
  while (ok && (n = fread(buffer, 1, sizeof buffer, in)) > 0) ok = fwrite(buffer, 1, n, out) == n;
  if (in != NULL) fclose(in);
  if (out != NULL) ok = fclose(out) == 0 && ok;
  return ok;
}

/* A plan in the format of lib/io/plan_file.hpp. */
static void plan_text(char* out, size_t size, const char* surface, const char* method, const char* network,
                      const char* extra_plan_line) {
  const int written = snprintf(out, size,
                               "# written by test_capi_plan\n"
                               "[plan]\n"
                               "schema_version = 1\n"
                               "surface = \"%s\"\n"
                               "method = \"%s\"\n"
                               "network = \"%.4000s\"\n"
                               "%s"
                               "target = 0.0025\n"
                               "margin = 0.8\n"
                               "reached = true\n"
                               "[domain]\n"
                               "deck = \"deck.inp\"\n"
                               "pair = 0\n"
                               "deformation = 0.1\n"
                               "capture = 0.5\n"
                               "normal_tilt_tangent = 0.1\n"
                               "boundary_fraction = 0.2\n"
                               "heldout_count = 100\n"
                               "heldout_seed = 1001\n",
                               surface, method, network, extra_plan_line);
  expect(written > 0 && (size_t)written < size, "the plan text fits its buffer");
}

/* Queries near a slightly warped, slightly sheared unit segment (Gregory rows: node normals tilted a little).
 */
static void make_queries(double* raw, int columns) {
  int i;
  for (i = 0; i < QUERIES; ++i) {
    const double t = (double)i / QUERIES;
    double* q = raw + (size_t)i * (size_t)columns;
    const double nodes[15] = {
        0.0,  0.0, 0.0,  1.0,           0.05,           0.02,          1.1, 0.95, -0.03 + 0.05 * t,
        0.02, 1.0, 0.01, 0.1 + 0.8 * t, 0.85 - 0.7 * t, 0.05 + 0.1 * t};
    memcpy(q, nodes, sizeof nodes);
    if (columns == 27) {
      const double normals[12] = {0.02, -0.01, 1.0, -0.03, 0.02, 1.0, 0.01, 0.04, 1.0, 0.0, -0.02, 1.0};
      memcpy(q + 15, normals, sizeof normals);
    }
  }
}

/* The plan's search and the search made directly give the same bits. */
static void expect_same_search(const char* plan, int surface, const char* method, const char* network,
                               const char* what) {
  contactnn_search *from_plan = NULL, *direct = NULL;
  double raw[QUERIES * 27], p1[2 * QUERIES], p2[2 * QUERIES], g1[QUERIES], g2[QUERIES];
  int s1[QUERIES], s2[QUERIES], it1[QUERIES], it2[QUERIES];
  const int columns = contactnn_raw_columns(surface);
  int code = contactnn_search_create_from_plan(&from_plan, plan, NULL);
  printf("%-44s -> %d %s\n", what, code, code ? contactnn_last_error() : "");
  expect(code == CONTACTNN_SUCCESS && from_plan != NULL, what);
  if (from_plan == NULL) return;
  expect(contactnn_search_surface(from_plan) == surface, "the plan's search has the plan's surface");
  expect(strcmp(contactnn_search_method(from_plan), method) == 0, "the plan's search has the plan's method");
  code = contactnn_search_create(&direct, surface, method, network, NULL);
  expect(code == CONTACTNN_SUCCESS, "the same search made directly");
  make_queries(raw, columns);
  memset(p1, 0, sizeof p1);
  memset(p2, 0, sizeof p2);
  expect(contactnn_search_run(from_plan, QUERIES, raw, p1, g1, s1, it1) == CONTACTNN_SUCCESS,
         "run the plan's search");
  expect(contactnn_search_run(direct, QUERIES, raw, p2, g2, s2, it2) == CONTACTNN_SUCCESS,
         "run the direct search");
  expect(memcmp(p1, p2, sizeof p1) == 0 && memcmp(g1, g2, sizeof g1) == 0 && memcmp(s1, s2, sizeof s1) == 0 &&
             memcmp(it1, it2, sizeof it1) == 0,
         "the plan's search gives the direct search's results bit for bit");
  expect(s1[0] == CONTACTNN_STATUS_OK || s1[0] == CONTACTNN_STATUS_OUT_OF_DOMAIN, "a usable answer");
  contactnn_search_destroy(from_plan);
  contactnn_search_destroy(direct);
}

/* A plan that must be refused with `code` and a message containing `needle`. */
static void expect_refused(const char* plan, int code, const char* needle, const char* what) {
  contactnn_search* search = (contactnn_search*)&failures; /* not NULL: a failed create must clear it */
  const int result = contactnn_search_create_from_plan(&search, plan, NULL);
  expect_refusal(result, search, code, needle, what);
}

int main(int argc, char** argv) {
  char net[4096], path[4096], text[16384], needle[8192], plan_dir[4096];
  if (argc != 3) {
    printf("usage: test_capi_plan SOURCE_DIR WORK_DIR\n");
    return 2;
  }

  /* 1. A plan without a network. */
  snprintf(path, sizeof path, "%.4000s/closed.toml", argv[2]);
  plan_text(text, sizeof text, "bilinear", "closed_form+newton:1", "", "");
  expect(write_text(path, text), "write closed.toml");
  expect_same_search(path, CONTACTNN_SURFACE_BILINEAR, "closed_form+newton:1", NULL,
                     "plan without a network");

  /* 2. A plan with a network file beside it (a relative path: resolved against the plan's directory; this
   *    process's working directory is elsewhere). */
  snprintf(plan_dir, sizeof plan_dir, "%.4000s/study", argv[2]);
  snprintf(net, sizeof net, "%.4000s/data/weights/gregory-48.h5", argv[1]);
  snprintf(path, sizeof path, "%.4000s/scene.h5", plan_dir);
  expect(copy_file(net, path), "copy the network beside the plan (WORK_DIR/study must exist)");
  snprintf(path, sizeof path, "%.4000s/plan.toml", plan_dir);
  plan_text(text, sizeof text, "gregory", "network+newton:1", "scene.h5", "");
  expect(write_text(path, text), "write study/plan.toml");
  expect_same_search(path, CONTACTNN_SURFACE_GREGORY, "network+newton:1", net, "plan with a network");

  /* 3. Refused plans: an unknown key (line 7), a missing field, a missing network file, a missing plan. */
  snprintf(path, sizeof path, "%.4000s/unknown.toml", argv[2]);
  plan_text(text, sizeof text, "bilinear", "newton:2", "", "colour = \"blue\"\n");
  expect(write_text(path, text), "write unknown.toml");
  snprintf(needle, sizeof needle, "'%.4000s':7: unknown key 'colour' in [plan]", path);
  expect_refused(path, CONTACTNN_ERROR_FORMAT, needle, "a plan with an unknown key");

  snprintf(path, sizeof path, "%.4000s/missing-field.toml", argv[2]);
  plan_text(text, sizeof text, "bilinear", "newton:2", "", "");
  *strstr(text, "method = ") = '#'; /* the method line becomes a comment */
  expect(write_text(path, text), "write missing-field.toml");
  snprintf(needle, sizeof needle, "'%.4000s':2: [plan] has no key 'method' (required)", path);
  expect_refused(path, CONTACTNN_ERROR_FORMAT, needle, "a plan without a method");

  snprintf(path, sizeof path, "%.4000s/no-network.toml", argv[2]);
  plan_text(text, sizeof text, "gregory", "network", "absent.h5", "");
  expect(write_text(path, text), "write no-network.toml");
  expect_refused(path, CONTACTNN_ERROR_IO, "absent.h5", "a plan whose network file is missing");

  snprintf(path, sizeof path, "%.4000s/other-surface.toml", argv[2]);
  snprintf(net, sizeof net, "%.4000s/data/weights/bilinear-8.h5", argv[1]);
  plan_text(text, sizeof text, "gregory", "network", net, "");
  expect(write_text(path, text), "write other-surface.toml");
  expect_refused(path, CONTACTNN_ERROR_FORMAT, "is a bilinear network",
                 "a plan whose network is of the other surface");

  snprintf(path, sizeof path, "%.4000s/none.toml", argv[2]);
  expect_refused(path, CONTACTNN_ERROR_IO, "none.toml", "a plan that does not exist");
  /* Issue 39: a directory is a plan that cannot be read (IO, as contactnn.h says; it was FORMAT). */
  expect_refused(argv[2], CONTACTNN_ERROR_IO, "is a directory", "a plan path that is a directory");
  expect_refused("", CONTACTNN_ERROR_INVALID_ARGUMENT, "plan_file is empty", "an empty plan path");
  {
    contactnn_search* search = NULL;
    expect(contactnn_search_create_from_plan(&search, NULL, NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT,
           "a NULL plan path");
    expect(contactnn_search_create_from_plan(NULL, path, NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT,
           "a NULL handle pointer");
  }
  expect(strcmp(contactnn_search_method(NULL), "") == 0, "no method for NULL");

  if (failures == 0) printf("PASS: every plan check holds\n");
  return failures == 0 ? 0 : 1;
}
