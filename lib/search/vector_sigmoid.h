/* vector_sigmoid.h: exp and the unit activation of paper Eq 12, O = 1 / (1 + exp(-gain U)), written so that a
 * compiler vectorises a loop over them (no library call, no branch): range reduction x = n ln2 + r with
 * |r| <= ln2 / 2, a polynomial for exp(r), and 2^n built in the exponent bits. C99 that is also valid C++;
 * lib/search uses it, and an exported C header can embed it. Needs <stdint.h> and <string.h> (a bit copy).
 *
 * Accuracy (tests/search/test_vector_sigmoid.cpp checks it against std::exp): cnn_exp within 2 ulp of exp on
 * [-700, 700]; cnn_expf within 2 ulp of expf on [-87, 88]. Inputs beyond are clamped to those ranges (so
 * nothing overflows). cnn_sigmoid / cnn_sigmoidf clamp gain U to +-700 / +-80: outputs are then exact to a
 * few ulps down to 1e-304 / 1.8e-35 and never below; above 1 - eps they are 1.
 */
#ifndef CONTACTNN_VECTOR_SIGMOID_H
#define CONTACTNN_VECTOR_SIGMOID_H

/* Raised whenever what this file computes or its interface changes: an exported header checks that the copy
 * in force (the first one included in a translation unit) is the one it was generated with. */
#define CNN_VECTOR_SIGMOID_VERSION 1

#include <stdint.h>
#include <string.h>

#if defined(__GNUC__)
#define CNN_VS_INLINE static inline __attribute__((always_inline))
#else
#define CNN_VS_INLINE static inline
#endif

/* exp(x) for x already in [-700, 700] (cnn_exp clamps). */
CNN_VS_INLINE double cnn_exp_core(double x) {
  /* Cody-Waite: ln2 = hi + lo with hi exact in 32 bits, so n * hi is exact for |n| < 2^20. */
  const double log2e = 1.4426950408889634074, ln2_hi = 6.93147180369123816490e-01,
               ln2_lo = 1.90821492927058770002e-10;
  const double shifter = 6755399441055744.0; /* 1.5 * 2^52: t - shifter is x log2(e) rounded to an integer */
  double t, n, r, p, two_n;
  int64_t bits;
  t = x * log2e + shifter;
  n = t - shifter;
  r = x - n * ln2_hi;
  r = r - n * ln2_lo;
  /* Taylor to degree 13 on |r| <= 0.347: truncation below 5e-18 relative. */
  p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * (r * r) + r;
  p = p + 1.0;
  /* The low bits of t hold n (t and the shifter share their exponent): 2^n = (n + 1023) << 52. */
  memcpy(&bits, &t, sizeof bits);
  bits = (bits - (int64_t)0x4338000000000000 + 1023) << 52;
  memcpy(&two_n, &bits, sizeof two_n);
  return p * two_n;
}

/* expf(x) for x already in [-87, 88] (cnn_expf clamps). */
CNN_VS_INLINE float cnn_expf_core(float x) {
  /* Cephes expf: ln2 = c1 + c2 with c1 exact in 9 bits; degree-6 polynomial, 4e-9 relative on |r| <= ln2/2.
   */
  const float log2e = 1.44269504088896341f, c1 = 0.693359375f, c2 = -2.12194440e-4f;
  const float shifter = 12582912.0f; /* 1.5 * 2^23 */
  float t, n, r, p, two_n;
  int32_t bits;
  t = x * log2e + shifter;
  n = t - shifter;
  r = x - n * c1;
  r = r - n * c2;
  p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = p * (r * r) + r;
  p = p + 1.0f;
  memcpy(&bits, &t, sizeof bits);
  bits = (bits - (int32_t)0x4B400000 + 127) << 23;
  memcpy(&two_n, &bits, sizeof two_n);
  return p * two_n;
}

/* The clamps are written as x86's min/max take them (a NaN passes through), so that each is one instruction.
 */
CNN_VS_INLINE double cnn_exp(double x) {
  x = x > 700.0 ? 700.0 : x;
  x = x < -700.0 ? -700.0 : x;
  return cnn_exp_core(x);
}

CNN_VS_INLINE float cnn_expf(float x) {
  x = x > 88.0f ? 88.0f : x;
  x = x < -87.0f ? -87.0f : x;
  return cnn_expf_core(x);
}

/* Eq 12 with gain = 2 / U0. */
CNN_VS_INLINE double cnn_sigmoid(double u, double gain) {
  double z = -gain * u;
  z = z > 700.0 ? 700.0 : z;
  z = z < -700.0 ? -700.0 : z;
  return 1.0 / (1.0 + cnn_exp_core(z));
}

CNN_VS_INLINE float cnn_sigmoidf(float u, float gain) {
  float z = -gain * u;
  z = z > 80.0f ? 80.0f : z;
  z = z < -80.0f ? -80.0f : z;
  return 1.0f / (1.0f + cnn_expf_core(z));
}

#endif /* CONTACTNN_VECTOR_SIGMOID_H */
