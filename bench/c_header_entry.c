/* The exported headers of the shipped bilinear-8 and gregory-48 networks (generated at build time by
 * export_header), compiled as C99 the way an FE code compiles them, for bench_search's c-header rows: both
 * headers in this one translation unit. */
#include <stddef.h>

#include "bilinear_8.h"
#include "gregory_48.h"

void cnn_bench_c_header_one(int gregory, size_t n, const double* raw, double* out, int* status);
void cnn_bench_c_header_batch(int gregory, size_t n, const double* raw, double* out, int* status);

/* One call per query, as an FE code calls the one-query function per pair. */
void cnn_bench_c_header_one(int gregory, size_t n, const double* raw, double* out, int* status) {
  size_t i;
  for (i = 0; i < n; ++i) {
    status[i] = gregory ? gregory_48_local_coordinates(raw + 27 * i, out + 2 * i)
                        : bilinear_8_local_coordinates(raw + 15 * i, out + 2 * i);
  }
}

void cnn_bench_c_header_batch(int gregory, size_t n, const double* raw, double* out, int* status) {
  if (gregory) {
    gregory_48_local_coordinates_batch(n, raw, out, status);
  } else {
    bilinear_8_local_coordinates_batch(n, raw, out, status);
  }
}
