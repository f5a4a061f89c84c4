/* test_capi_faces: the faces of SPEC 9 beside the 4-node quads through the C interface
 * (CONTACTNN_SURFACE_TRI3, _TRI6, _QUAD8): answers known in closed form (flat faces: the projection; a curved
 * quad8 symmetric about its centre with S on the axis: the centre), the raw row sizes, and the refusals (a
 * network on tri3, four_triangles, a network file of another kind). Exit status 0 when every check holds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contactnn/contactnn.h"

static int failures = 0;

static void expect(int condition, const char* what) {
  if (!condition) {
    ++failures;
    fprintf(stderr, "FAILED: %s (%s)\n", what, contactnn_last_error());
  }
}

/* A valid network file of the other kind (`path`) given to a search of `surface`: INVALID_ARGUMENT, no
 * handle, and a message containing `needle` that says what the file is. */
static void expect_other_kind(int surface, const char* path, const char* needle, const char* what) {
  contactnn_search* s = (contactnn_search*)&failures; /* not NULL: a failed create must clear it */
  expect(contactnn_search_create(&s, surface, "network", path, NULL) == CONTACTNN_ERROR_INVALID_ARGUMENT &&
             s == NULL,
         what);
  expect(strstr(contactnn_last_error(), needle) != NULL, "the message says what the file is");
}

static void run_one(int surface, const char* method, const double* raw, double* param, double* gap,
                    int* status) {
  contactnn_search* s = NULL;
  char what[200];
  snprintf(what, sizeof what, "create surface %d, %s", surface, method);
  expect(contactnn_search_create(&s, surface, method, NULL, NULL) == CONTACTNN_SUCCESS, what);
  if (s == NULL) return;
  expect(contactnn_search_surface(s) == surface, "the search's surface");
  expect(strcmp(contactnn_search_method(s), method) == 0, "the search's method");
  snprintf(what, sizeof what, "run surface %d, %s", surface, method);
  expect(contactnn_search_run(s, 1, raw, param, gap, status, NULL) == CONTACTNN_SUCCESS, what);
  contactnn_search_destroy(s);
}

int main(int argc, char** argv) {
  double param[2], gap;
  int status;
  (void)argc;
  expect(contactnn_raw_columns(CONTACTNN_SURFACE_TRI3) == 12, "tri3 rows of 12 values");
  expect(contactnn_raw_columns(CONTACTNN_SURFACE_TRI6) == 21, "tri6 rows of 21 values");
  expect(contactnn_raw_columns(CONTACTNN_SURFACE_QUAD8) == 27, "quad8 rows of 27 values");
  expect(contactnn_raw_columns(5) == 0, "no surface 5");
  {
    /* tri3 (0,0,0), (2,0,0), (0,2,0); S = (0.4, 0.6, -0.25): (r, s) = (0.2, 0.3), gap -0.25. */
    const double raw[12] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.4, 0.6, -0.25};
    const char* methods[] = {"closed_form", "newton:1", "newton"};
    for (int m = 0; m < 3; ++m) {
      run_one(CONTACTNN_SURFACE_TRI3, methods[m], raw, param, &gap, &status);
      expect(status == CONTACTNN_STATUS_OK && fabs(param[0] - 0.2) < 1e-14 && fabs(param[1] - 0.3) < 1e-14 &&
                 fabs(gap + 0.25) < 1e-14,
             methods[m]);
    }
  }
  {
    /* tri6, flat, mid-side nodes at the midpoints: the same answer. */
    const double raw[21] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.4, 0.6, 0.5};
    const char* methods[] = {"closed_form", "newton:2", "newton", "closed_form+newton:1"};
    for (int m = 0; m < 4; ++m) {
      run_one(CONTACTNN_SURFACE_TRI6, methods[m], raw, param, &gap, &status);
      expect(status == CONTACTNN_STATUS_OK && fabs(param[0] - 0.2) < 1e-12 && fabs(param[1] - 0.3) < 1e-12 &&
                 fabs(gap - 0.5) < 1e-12,
             methods[m]);
    }
  }
  {
    /* quad8 on the square [-1, 1]^2 with every mid-side node raised by 0.2: symmetric under the square's
     * symmetries, so S on the axis (0, 0, 2) has its closest point at the centre, P(0, 0) = (0, 0, -0.25 * 0
     * + 0.5 * 4 * 0.2) = (0, 0, 0.4), gap 1.6. */
    const double raw[27] = {-1,  -1, 0, 1,   -1, 0, 1,   1,  0, -1,  1, 0, 0, -1,
                            0.2, 1,  0, 0.2, 0,  1, 0.2, -1, 0, 0.2, 0, 0, 2};
    const char* methods[] = {"newton", "newton:3", "closed_form+newton:2"};
    for (int m = 0; m < 3; ++m) {
      run_one(CONTACTNN_SURFACE_QUAD8, methods[m], raw, param, &gap, &status);
      expect(status == CONTACTNN_STATUS_OK && fabs(param[0]) < 1e-12 && fabs(param[1]) < 1e-12 &&
                 fabs(gap - 1.6) < 1e-12,
             methods[m]);
    }
  }
  {
    contactnn_search* s = NULL;
    expect(contactnn_search_create(&s, CONTACTNN_SURFACE_TRI3, "network", "x.h5", NULL) ==
                   CONTACTNN_ERROR_INVALID_ARGUMENT &&
               s == NULL,
           "tri3 takes no network");
    expect(strstr(contactnn_last_error(), "closed form is exact") != NULL, "the message says why");
    expect(contactnn_search_create(&s, CONTACTNN_SURFACE_QUAD8, "four_triangles", NULL, NULL) ==
               CONTACTNN_ERROR_INVALID_ARGUMENT,
           "four_triangles is a 4-node quad's");
    if (argv[1] != NULL) {
      char path[4200];
      snprintf(path, sizeof path, "%s/data/weights/bilinear-8.h5", argv[1]);
      /* Issue 39: a valid network file of the other kind is a wrong argument, as a network of the other
       * surface or face type is (contactnn.h): INVALID_ARGUMENT, not FORMAT (which is for files that are no
       * network). */
      expect_other_kind(CONTACTNN_SURFACE_TRI6, path, "not a face network",
                        "a network file of train-net given to a face search is INVALID_ARGUMENT");
      snprintf(path, sizeof path, "%s/data/weights/tri6-48-48.h5", argv[1]);
      expect_other_kind(CONTACTNN_SURFACE_BILINEAR, path, "is a face network",
                        "a face network given to a bilinear search is INVALID_ARGUMENT");
    }
  }
  if (failures > 0) {
    fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  printf("PASS: the faces through the C interface\n");
  return 0;
}
