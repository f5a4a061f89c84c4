// Flush-to-zero and denormals-are-zero for the scope of a training computation.
//
// Late in training, momentum terms and gradients of saturated units decay through the subnormal range;
// subnormal arithmetic costs tens to hundreds of cycles per operation on x86, and turned the online
// epoch several times slower in measurements. Values that small (< 1.2e-38 in float) do not change any
// weight, so flushing them changes no result that matters. The previous mode is restored on exit.
#pragma once

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace contactnn::mlp {

class ScopedFlushDenormals {
 public:
#if defined(__SSE__) || defined(__x86_64__)
  ScopedFlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~ScopedFlushDenormals() { _mm_setcsr(saved_); }

 private:
  static constexpr unsigned kFlushToZero = 0x8000;
  static constexpr unsigned kDenormalsAreZero = 0x0040;
  unsigned saved_;
#else
  ScopedFlushDenormals() = default;
#endif
 public:
  ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
  ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;
};

}  // namespace contactnn::mlp
