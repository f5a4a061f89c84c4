/* The canonical-frame kernel and the vectorisable sigmoid compiled as C99 (-std=c99 -pedantic -Werror, see
 * CMakeLists.txt), each included twice as two exported headers in one translation unit would include them. */
#include "search/canonical_frame.h"
#include "search/vector_sigmoid.h"

void contactnn_canonicalise_c99(int n, int gregory, const double* in, double* f, double* nrm, double* info);
int contactnn_forms_c99(const double* x, int gregory, double* f, double* nrm, double* info);
double contactnn_sigmoid_c99(double u, double gain);
float contactnn_sigmoidf_c99(float u, float gain);

void contactnn_canonicalise_c99(int n, int gregory, const double* in, double* f, double* nrm, double* info) {
  cnn_canonicalise_block(n, gregory, in, f, nrm, info);
}
int contactnn_forms_c99(const double* x, int gregory, double* f, double* nrm, double* info) {
  return cnn_cf_forms(x, gregory, f, nrm, info);
}
double contactnn_sigmoid_c99(double u, double gain) { return cnn_sigmoid(u, gain); }
float contactnn_sigmoidf_c99(float u, float gain) { return cnn_sigmoidf(u, gain); }
