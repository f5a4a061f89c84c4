/* canonical_frame_base.h (part of canonical_frame.h): what every part of the canonical-frame kernel uses: the
 * compiler hints that let the loops over lanes vectorise, the status codes and rows of `info`, and max and
 * min with std::max and std::min's semantics in double and float. */
#ifndef CONTACTNN_CANONICAL_FRAME_BASE_H
#define CONTACTNN_CANONICAL_FRAME_BASE_H

#include <math.h>
#include <string.h>

#if defined(__cplusplus)
#define CNN_CF_RESTRICT __restrict
#else
#define CNN_CF_RESTRICT restrict
#endif

/* The lane functions must be inlined into the loops over lanes, or nothing vectorises. */
#if defined(__GNUC__)
#define CNN_CF_INLINE static inline __attribute__((always_inline))
#else
#define CNN_CF_INLINE static inline
#endif

/* Code off the hot path: kept out of the callers (a caller's loops are otherwise compiled around its arrays).
 */
#if defined(__GNUC__)
#define CNN_CF_OUTLINE static __attribute__((noinline, unused))
#else
#define CNN_CF_OUTLINE static inline
#endif

/* Lanes never alias one another: the loops over lanes carry no dependence. */
#if defined(__clang__)
#define CNN_CF_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define CNN_CF_IVDEP _Pragma("GCC ivdep")
#else
#define CNN_CF_IVDEP
#endif

/* Short loops inside a lane must be unrolled before the loop over lanes can vectorise. */
#if defined(__clang__)
#define CNN_CF_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define CNN_CF_UNROLL _Pragma("GCC unroll 16")
#else
#define CNN_CF_UNROLL
#endif

#define CNN_CF_STATUS_OK 0
#define CNN_CF_STATUS_DEGENERATE 3
#define CNN_CF_STATUS_INVALID 4
#define CNN_CF_STATUS_OUT_OF_DOMAIN 5

/* Rows of `info` per lane, and the most canonical forms a query can have (4 tied nodes x 2 mirrors, x 2
 * orientations of z; geometry::kMaxCanonicalForms). */
#define CNN_CF_INFO_ROWS 6
#define CNN_CF_MAX_FORMS 16

/* std::max / std::min semantics (the first argument when the comparison is false). */
CNN_CF_INLINE double cnn_cf_max(double a, double b) { return a < b ? b : a; }
CNN_CF_INLINE double cnn_cf_min(double a, double b) { return b < a ? b : a; }
/* cnn_cf_max and cnn_cf_min in float (fmaxf and fminf do not vectorise: their NaN rule is not the
 * instruction's). */
CNN_CF_INLINE float cnn_cff_max(float a, float b) { return a < b ? b : a; }
CNN_CF_INLINE float cnn_cff_min(float a, float b) { return b < a ? b : a; }

#endif /* CONTACTNN_CANONICAL_FRAME_BASE_H */
