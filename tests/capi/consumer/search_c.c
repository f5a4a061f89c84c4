/* search_c: contactnn's C interface as a finite-element code calls it, on a file of queries.
 *
 * Usage: search_c bilinear|gregory METHOD NETWORK RAW.txt OUT.txt double|float
 *   RAW.txt  the query count n on the first line, then n rows of 15 (bilinear) or 27 (Gregory) numbers in
 *            SPEC 6's column order (nan and inf allowed)
 *   OUT.txt  one line per query: p0 p1 status gap iterations
 * Exit status 0, or 1 with contactnn's message on stderr. */
#include <contactnn/contactnn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(const char* what) {
  fprintf(stderr, "search_c: %s: %s\n", what, contactnn_last_error());
  return 1;
}

int main(int argc, char** argv) {
  contactnn_options options;
  contactnn_search* search = NULL;
  FILE* in;
  FILE* out;
  unsigned long count = 0;
  size_t n, i, k;
  int surface, columns, use_float;
  double* raw;
  double* param;
  double* gap;
  int* status;
  int* iterations;

  if (argc != 7) {
    fprintf(stderr, "usage: search_c bilinear|gregory METHOD NETWORK RAW.txt OUT.txt double|float\n");
    return 2;
  }
  surface = strcmp(argv[1], "gregory") == 0 ? CONTACTNN_SURFACE_GREGORY : CONTACTNN_SURFACE_BILINEAR;
  columns = contactnn_raw_columns(surface);
  use_float = strcmp(argv[6], "float") == 0;

  /* 1. The queries. */
  in = fopen(argv[4], "r");
  if (in == NULL || fscanf(in, "%lu", &count) != 1) {
    fprintf(stderr, "search_c: cannot read the count from %s\n", argv[4]);
    return 1;
  }
  n = count;
  raw = malloc(n * (size_t)columns * sizeof *raw);
  param = malloc(2 * n * sizeof *param);
  gap = malloc(n * sizeof *gap);
  status = malloc(n * sizeof *status);
  iterations = malloc(n * sizeof *iterations);
  if (n > 0 && (raw == NULL || param == NULL || gap == NULL || status == NULL || iterations == NULL))
    return 1;
  for (k = 0; k < n * (size_t)columns; ++k) {
    if (fscanf(in, "%lf", &raw[k]) != 1) {
      fprintf(stderr, "search_c: %s: value %lu does not parse\n", argv[4], (unsigned long)k);
      return 1;
    }
  }
  fclose(in);

  /* 2. The search: two threads, every other option at its default. */
  if (contactnn_options_init(&options) != CONTACTNN_SUCCESS) return fail("contactnn_options_init");
  options.threads = 2;
  if (contactnn_search_create(&search, surface, argv[2], argv[3], &options) != CONTACTNN_SUCCESS) {
    return fail("contactnn_search_create");
  }

  /* 3. One batched call for all queries, in the precision asked for. */
  if (use_float) {
    float* raw_f = malloc(n * (size_t)columns * sizeof *raw_f);
    float* param_f = malloc(2 * n * sizeof *param_f);
    float* gap_f = malloc(n * sizeof *gap_f);
    if (n > 0 && (raw_f == NULL || param_f == NULL || gap_f == NULL)) return 1;
    for (k = 0; k < n * (size_t)columns; ++k) raw_f[k] = (float)raw[k];
    if (contactnn_search_run_float(search, n, raw_f, param_f, gap_f, status, iterations) !=
        CONTACTNN_SUCCESS) {
      return fail("contactnn_search_run_float");
    }
    for (k = 0; k < 2 * n; ++k) param[k] = param_f[k];
    for (k = 0; k < n; ++k) gap[k] = gap_f[k];
    free(raw_f);
    free(param_f);
    free(gap_f);
  } else if (contactnn_search_run(search, n, raw, param, gap, status, iterations) != CONTACTNN_SUCCESS) {
    return fail("contactnn_search_run");
  }
  contactnn_search_destroy(search);

  /* 4. The results. */
  out = fopen(argv[5], "w");
  if (out == NULL) return 1;
  for (i = 0; i < n; ++i) {
    fprintf(out, "%.17g %.17g %d %.17g %d\n", param[2 * i], param[2 * i + 1], status[i], gap[i],
            iterations[i]);
  }
  fclose(out);
  printf("search_c: contactnn %s, %lu queries, %s\n", contactnn_version(NULL, NULL, NULL), (unsigned long)n,
         use_float ? "float" : "double");
  free(raw);
  free(param);
  free(gap);
  free(status);
  free(iterations);
  return 0;
}
