/* test_threads: a run takes OpenMP's default thread count capped at CONTACTNN_MAX_THREADS. ctest runs it with
 * OMP_NUM_THREADS=100000, which libgomp accepts and then cannot start: before the cap, the first parallel run
 * ended the process inside libgomp ("Thread creation failed").
 *
 * Usage: test_capi_threads. Exit status 0 when a parallel run on every query succeeds with the right answer.
 */
#include <contactnn/contactnn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

enum { kCount = 4096 };

static double raw[kCount * 15], param[kCount * 2], gap[kCount];
static int status[kCount];

int main(void) {
  contactnn_search* search = NULL;
  contactnn_options options;
  const char* asked = getenv("OMP_NUM_THREADS");
  size_t i;
  int failures = 0;

  printf("OMP_NUM_THREADS=%s\n", asked != NULL ? asked : "(unset)");
  /* The unit square A = 0, B = x, C = x + y, D = y; S above it at (x, y, 0.1): xi = 2x - 1, eta = 2y - 1. */
  for (i = 0; i < kCount; ++i) {
    double* r = raw + 15 * i;
    const double x = 0.05 + 0.9 * (double)(i % 61) / 61.0, y = 0.05 + 0.9 * (double)(i % 47) / 47.0;
    const double square[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    size_t k;
    for (k = 0; k < 12; ++k) r[k] = square[k];
    r[12] = x;
    r[13] = y;
    r[14] = 0.1;
  }
  if (contactnn_options_init(&options) != CONTACTNN_SUCCESS) return 1;
  options.min_parallel_count = 1; /* every batch in parallel */
  if (contactnn_search_create(&search, CONTACTNN_SURFACE_BILINEAR, "newton:4", NULL, &options) !=
      CONTACTNN_SUCCESS) {
    printf("FAIL: create: %s\n", contactnn_last_error());
    return 1;
  }
  if (contactnn_search_run(search, kCount, raw, param, gap, status, NULL) != CONTACTNN_SUCCESS) {
    printf("FAIL: run: %s\n", contactnn_last_error());
    ++failures;
  }
  for (i = 0; i < kCount && failures == 0; ++i) {
    const double* r = raw + 15 * i;
    if (status[i] != CONTACTNN_STATUS_OK || fabs(param[2 * i] - (2 * r[12] - 1)) > 1e-9 ||
        fabs(param[2 * i + 1] - (2 * r[13] - 1)) > 1e-9 || fabs(gap[i] - 0.1) > 1e-9) {
      printf("FAIL: query %lu: status %d, (%g, %g), gap %g\n", (unsigned long)i, status[i], param[2 * i],
             param[2 * i + 1], gap[i]);
      ++failures;
    }
  }
  contactnn_search_destroy(search);
  if (failures == 0) printf("a parallel run of %d queries succeeds\n", kCount);
  return failures == 0 ? 0 : 1;
}
