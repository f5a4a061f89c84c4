/* test_errors: the C interface's error paths, from C99. Every bad call returns its documented code, leaves
 * a message naming what was wrong, writes no handle, and the process goes on (no exception, no abort).
 *
 * Usage: test_capi_errors SOURCE_DIR   (for data/weights and data/examples). Exit status 0 when every
 * check holds; each failed check is printed. */
#include <contactnn/contactnn.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refusal_check.h"

/* A creation that must fail with `code` and a message containing `needle`. */
static void expect_create_fails(int surface, const char* method, const char* network,
                                const contactnn_options* options, int code, const char* needle,
                                const char* what) {
  contactnn_search* search = (contactnn_search*)&failures; /* not NULL: a failed create must clear it */
  const int result = contactnn_search_create(&search, surface, method, network, options);
  expect_refusal(result, search, code, needle, what);
  /* The user's message alone: no internal condition or source path (those are for broken invariants). */
  if (strstr(contactnn_last_error(), "[requirement") != NULL ||
      strstr(contactnn_last_error(), ".cpp:") != NULL) {
    printf("FAIL: %s: the message shows the library's source\n", what);
    ++failures;
  }
}

int main(int argc, char** argv) {
  char bilinear_net[4096], gregory_net[4096], csv[4096], missing[4096];
  contactnn_options options;
  contactnn_search* search = NULL;
  double raw[15] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.25, 0.5, 0.1};
  double param[2], gap;
  int status = -1, iterations = -1, major = -1, minor = -1, patch = -1;
  char version[64];

  if (argc != 2) {
    printf("usage: test_capi_errors SOURCE_DIR\n");
    return 2;
  }
  sprintf(bilinear_net, "%.4000s/data/weights/bilinear-8.h5", argv[1]);
  sprintf(gregory_net, "%.4000s/data/weights/gregory-48.h5", argv[1]);
  sprintf(csv, "%.4000s/data/examples/raw-bilinear.csv", argv[1]);
  sprintf(missing, "%.4000s/data/weights/no-such-network.h5", argv[1]);

  /* 1. Before anything failed, the message is empty; version and the fixed tables. */
  expect(strcmp(contactnn_last_error(), "") == 0, "no message before any failure");
  strcpy(version, contactnn_version(&major, &minor, &patch));
  {
    char numbers[64];
    sprintf(numbers, "%d.%d.%d", major, minor, patch);
    expect(strcmp(version, numbers) == 0, "the version string spells the version numbers");
  }
  expect(strcmp(contactnn_version(NULL, NULL, NULL), version) == 0, "contactnn_version accepts NULL numbers");
  expect(strcmp(contactnn_status_name(CONTACTNN_STATUS_OUT_OF_DOMAIN), "out_of_domain") == 0,
         "status name 5");
  expect(
      strcmp(contactnn_status_name(7), "unknown") == 0 && strcmp(contactnn_status_name(-1), "unknown") == 0,
      "status names outside 0..6 are unknown");
  expect(contactnn_raw_columns(CONTACTNN_SURFACE_BILINEAR) == 15 &&
             contactnn_raw_columns(CONTACTNN_SURFACE_GREGORY) == 27 && contactnn_raw_columns(5) == 0,
         "raw columns 15, 27, 0");

  /* 2. Creation. */
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "netwrok", bilinear_net, NULL,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "netwrok", "a misspelt method");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "newton:-2", NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                      "newton:-2", "a negative step count");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, NULL, NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                      "method is NULL", "a NULL method");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network", NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                      "needs a network file", "a network method without a file");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network+newton:2", "", NULL,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "needs a network file",
                      "a hybrid with an empty file name");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network", missing, NULL, CONTACTNN_ERROR_IO,
                      "no-such-network.h5", "a missing network file");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network", csv, NULL, CONTACTNN_ERROR_FORMAT,
                      "raw-bilinear.csv", "a CSV file as the network");
  expect_create_fails(5, "newton:5", NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT, "surface = 5",
                      "surface 5 (the faces end at CONTACTNN_SURFACE_QUAD8, 4)");
  expect_create_fails(-1, "newton:5", NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT, "surface = -1",
                      "surface -1");
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network", gregory_net, NULL,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "gregory network",
                      "a Gregory network for bilinear surfaces");
  expect_create_fails(CONTACTNN_SURFACE_GREGORY, "network", bilinear_net, NULL,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "bilinear network",
                      "a bilinear network for Gregory surfaces");
  expect_create_fails(CONTACTNN_SURFACE_GREGORY, "closed_form+newton:", NULL, NULL,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "closed_form+newton:K",
                      "a hybrid without its step count");
  expect(contactnn_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
  options.max_iterations = 0;
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "newton", NULL, &options, CONTACTNN_ERROR_INVALID_ARGUMENT,
                      "max_iterations = 0", "max_iterations 0");
  expect(contactnn_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
  options.max_step_widths = -1.0;
  expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "closed_form+newton:1", NULL, &options,
                      CONTACTNN_ERROR_INVALID_ARGUMENT, "max_step_widths", "a negative step cap");
  /* Issue 39: every option outside its documented range (contactnn.h), each of which made a run hang or every
   * answer ok, refused with the field and its range named; on the curved faces where they hung. */
  {
    struct {
      const char* field;
      int surface;
      const char* method;
      int max_iterations, max_halvings;
      double tol_param, domain_margin, gregory_box_margin, bilinear_box_margin, max_step_widths;
      const char* needle;
    } bad[] = {
        {"max_halvings INT_MAX", CONTACTNN_SURFACE_TRI6, "closed_form+newton:20", 50, INT_MAX, 1e-10, 1e-10,
         0, 0.25, 0.5, "max_halvings = 2147483647, expected 0 to 60"},
        {"max_halvings 61", CONTACTNN_SURFACE_BILINEAR, "closed_form+newton:2", 50, 61, 1e-10, 1e-10, 0, 0.25,
         0.5, "max_halvings = 61, expected 0 to 60"},
        {"max_iterations INT_MAX", CONTACTNN_SURFACE_TRI6, "newton", INT_MAX, 3, 1e-10, 1e-10, 0, 0.25, 0.5,
         "max_iterations = 2147483647, expected 1 to 1000"},
        {"max_iterations 1001", CONTACTNN_SURFACE_BILINEAR, "newton", 1001, 3, 1e-10, 1e-10, 0, 0.25, 0.5,
         "max_iterations = 1001, expected 1 to 1000"},
        {"domain_margin +inf", CONTACTNN_SURFACE_TRI6, "newton:5", 50, 3, 1e-10, INFINITY, 0, 0.25, 0.5,
         "domain_margin = inf, expected a finite number from 0 to 1"},
        {"domain_margin 2", CONTACTNN_SURFACE_BILINEAR, "newton:5", 50, 3, 1e-10, 2.0, 0, 0.25, 0.5,
         "domain_margin = 2, expected"},
        {"tol_param NaN", CONTACTNN_SURFACE_QUAD8, "newton", 50, 3, NAN, 1e-10, 0, 0.25, 0.5,
         "tol_param = nan"},
        {"tol_param +inf", CONTACTNN_SURFACE_BILINEAR, "newton", 50, 3, INFINITY, 1e-10, 0, 0.25, 0.5,
         "tol_param = inf, expected a finite number from 0 to 1"},
        {"gregory_box_margin +inf", CONTACTNN_SURFACE_GREGORY, "closed_form+newton:2", 50, 3, 1e-10, 1e-10,
         INFINITY, 0.25, 0.5, "gregory_box_margin = inf"},
        {"bilinear_box_margin 1e300", CONTACTNN_SURFACE_BILINEAR, "closed_form+newton:2", 50, 3, 1e-10, 1e-10,
         0, 1e300, 0.5, "bilinear_box_margin = 1e+300, expected a finite number from 0 to 1"},
        {"max_step_widths +inf", CONTACTNN_SURFACE_BILINEAR, "closed_form+newton:2", 50, 3, 1e-10, 1e-10, 0,
         0.25, INFINITY, "max_step_widths = inf, expected a finite number > 0 and <= 1"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
      expect(contactnn_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
      options.max_iterations = bad[i].max_iterations;
      options.max_halvings = bad[i].max_halvings;
      options.tol_param = bad[i].tol_param;
      options.domain_margin = bad[i].domain_margin;
      options.gregory_box_margin = bad[i].gregory_box_margin;
      options.bilinear_box_margin = bad[i].bilinear_box_margin;
      options.max_step_widths = bad[i].max_step_widths;
      expect_create_fails(bad[i].surface, bad[i].method, NULL, &options, CONTACTNN_ERROR_INVALID_ARGUMENT,
                          bad[i].needle, bad[i].field);
    }
    /* The ends of each range are accepted. */
    expect(contactnn_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
    options.max_iterations = 1000;
    options.max_halvings = 60;
    options.tol_param = 1.0;
    options.domain_margin = 1.0;
    options.gregory_box_margin = 1.0;
    options.bilinear_box_margin = 1.0;
    options.max_step_widths = 1.0;
    for (int surface = CONTACTNN_SURFACE_BILINEAR; surface <= CONTACTNN_SURFACE_QUAD8; ++surface) {
      contactnn_search* edge = NULL;
      expect(contactnn_search_create(&edge, surface, "closed_form+newton:2", NULL, &options) ==
                     CONTACTNN_SUCCESS &&
                 edge != NULL,
             "every option at the upper end of its range is accepted");
      contactnn_search_destroy(edge);
    }
  }
  expect(contactnn_search_create(NULL, CONTACTNN_SURFACE_BILINEAR, "newton:5", NULL, NULL) ==
             CONTACTNN_ERROR_INVALID_ARGUMENT,
         "a NULL handle pointer");
  expect(contactnn_options_init(NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT, "options_init(NULL)");

  /* 3. A good search; bad runs on it. */
  expect(contactnn_search_create(&search, CONTACTNN_SURFACE_BILINEAR, "network", bilinear_net, NULL) ==
             CONTACTNN_SUCCESS,
         "a good search is created");
  expect(strstr(contactnn_last_error(), "contactnn_options_init") != NULL,
         "a success leaves the last message unchanged");
  expect(
      contactnn_search_surface(search) == CONTACTNN_SURFACE_BILINEAR && contactnn_search_surface(NULL) == -1,
      "contactnn_search_surface");
  expect(contactnn_search_run(NULL, 1, raw, param, &gap, &status, &iterations) ==
                 CONTACTNN_ERROR_INVALID_ARGUMENT &&
             strstr(contactnn_last_error(), "search is NULL") != NULL,
         "a run without a search");
  expect(contactnn_search_run(search, 1, NULL, param, &gap, &status, &iterations) ==
                 CONTACTNN_ERROR_INVALID_ARGUMENT &&
             strstr(contactnn_last_error(), "raw NULL") != NULL,
         "a run without raw");
  expect(contactnn_search_run(search, 1, raw, param, &gap, NULL, &iterations) ==
                 CONTACTNN_ERROR_INVALID_ARGUMENT &&
             strstr(contactnn_last_error(), "status NULL") != NULL,
         "a run without status");
  expect(contactnn_search_run(search, (size_t)-1, raw, param, &gap, &status, &iterations) ==
                 CONTACTNN_ERROR_INVALID_ARGUMENT &&
             strstr(contactnn_last_error(), "overflow") != NULL,
         "a count that overflows");
  expect(contactnn_search_run(search, 0, NULL, NULL, NULL, NULL, NULL) == CONTACTNN_SUCCESS,
         "count 0 needs no arrays");

  /* 4. After all that, the search still works: S = (0.25, 0.5, 0.1) above the unit square A = 0, B = x, D = y
   *    projects to xi = 2 * 0.25 - 1, eta = 2 * 0.5 - 1 at gap 0.1 (within the network's accuracy). */
  expect(contactnn_search_run(search, 1, raw, param, &gap, &status, NULL) == CONTACTNN_SUCCESS, "a good run");
  expect(status == CONTACTNN_STATUS_OK || status == CONTACTNN_STATUS_OUT_OF_DOMAIN, "a good run's status");
  expect(fabs(param[0] + 0.5) < 0.2 && fabs(param[1]) < 0.2 && fabs(gap - 0.1) < 0.02,
         "a good run's answer is near (-0.5, 0), gap 0.1 (the 8-8-2 network's accuracy: 0.2)");
  contactnn_search_destroy(search);
  contactnn_search_destroy(NULL);

  /* 5. The handle's check value (contactnn.h, "Handles"): a destroyed search, or a pointer that is not a
   * search, answers INVALID_ARGUMENT instead of crashing, and a second destroy frees nothing. */
  expect(
      contactnn_search_run(search, 1, raw, param, &gap, &status, NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT &&
          strstr(contactnn_last_error(), "not a live handle") != NULL,
      "a run on a destroyed search");
  expect(
      contactnn_search_run_float(search, 0, NULL, NULL, NULL, NULL, NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT,
      "a float run on a destroyed search, even of 0 queries");
  expect(contactnn_search_surface(search) == -1, "the surface of a destroyed search is -1");
  contactnn_search_destroy(search);
  expect(strstr(contactnn_last_error(), "nothing was freed") != NULL, "a second destroy frees nothing");
  {
    double not_a_search[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    expect(contactnn_search_run((const contactnn_search*)not_a_search, 1, raw, param, &gap, &status, NULL) ==
                   CONTACTNN_ERROR_INVALID_ARGUMENT &&
               strstr(contactnn_last_error(), "not a live handle") != NULL,
           "a run on a pointer that is not a search");
    expect(contactnn_search_run((const contactnn_search*)&options, 1, raw, param, &gap, &status, NULL) ==
               CONTACTNN_ERROR_INVALID_ARGUMENT,
           "a run on the options struct given as a search");
    expect(contactnn_search_surface((const contactnn_search*)not_a_search) == -1,
           "the surface of a pointer that is not a search is -1");
  }

  /* 6. Limits: a method name of 10 MB is quoted short (not echoed whole, once per mention); a thread count
   *    above CONTACTNN_MAX_THREADS is refused (libgomp fails inside the run when it cannot start the team).
   */
  {
    const size_t digits = 10000000;
    char* huge = (char*)malloc(digits + 32);
    expect(huge != NULL, "memory for a 10 MB method name");
    if (huge != NULL) {
      strcpy(huge, "newton:");
      memset(huge + 7, '1', digits);
      huge[7 + digits] = '\0';
      expect_create_fails(CONTACTNN_SURFACE_BILINEAR, huge, NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                          "'newton:1111", "newton: and 10 MB of digits");
      expect(
          strlen(contactnn_last_error()) < 400 && strstr(contactnn_last_error(), "(10000007 bytes)") != NULL,
          "newton: and 10 MB of digits: the message quotes the method short");
      memset(huge, 'x', digits);
      huge[digits] = '\0';
      expect_create_fails(CONTACTNN_SURFACE_BILINEAR, huge, NULL, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                          "'xxxx", "a 10 MB method name");
      expect(
          strlen(contactnn_last_error()) < 400 && strstr(contactnn_last_error(), "(10000000 bytes)") != NULL,
          "a 10 MB method name: the message quotes it short");
      memset(huge, 'n', 5000);
      huge[5000] = '\0';
      expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "network", huge, NULL, CONTACTNN_ERROR_INVALID_ARGUMENT,
                          "longer than any path", "a network file name of 5000 bytes");
      free(huge);
    }
    expect(contactnn_options_init(&options) == CONTACTNN_SUCCESS, "options_init");
    options.threads = CONTACTNN_MAX_THREADS + 1;
    expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "newton:2", NULL, &options,
                        CONTACTNN_ERROR_INVALID_ARGUMENT, "options.threads = 1025",
                        "threads above CONTACTNN_MAX_THREADS");
    options.threads = 100000;
    expect_create_fails(CONTACTNN_SURFACE_BILINEAR, "newton:2", NULL, &options,
                        CONTACTNN_ERROR_INVALID_ARGUMENT, "options.threads = 100000", "threads 100000");
    options.threads = CONTACTNN_MAX_THREADS;
    expect(contactnn_search_create(&search, CONTACTNN_SURFACE_BILINEAR, "newton:2", NULL, &options) ==
               CONTACTNN_SUCCESS,
           "threads = CONTACTNN_MAX_THREADS is accepted");
    contactnn_search_destroy(search);
  }

  /* 7. Bindings record their own errors the same way. */
  expect(contactnn_set_last_error(CONTACTNN_ERROR_INVALID_ARGUMENT, "from a binding") ==
                 CONTACTNN_ERROR_INVALID_ARGUMENT &&
             strcmp(contactnn_last_error(), "from a binding") == 0,
         "contactnn_set_last_error");

  if (failures == 0) printf("all error paths behave\n");
  return failures == 0 ? 0 : 1;
}
