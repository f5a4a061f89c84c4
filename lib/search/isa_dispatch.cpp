// The choice of a kernel variant (isa_dispatch.hpp). Compiled like the rest of the library (any x86-64), with
// the list of the variants this build holds (CONTACTNN_KERNELS_<NAME>, lib/search/CMakeLists.txt).
#include "search/isa_dispatch.hpp"

#include <array>
#include <cstdlib>
#include <string>

#include "core/error.hpp"
#include "search/search_plan.hpp"

#if CONTACTNN_KERNELS_BASELINE
CONTACTNN_DECLARE_KERNEL_ISA(isa_baseline)
#endif
#if CONTACTNN_KERNELS_AVX2
CONTACTNN_DECLARE_KERNEL_ISA(isa_avx2)
#endif
#if CONTACTNN_KERNELS_AVX512
CONTACTNN_DECLARE_KERNEL_ISA(isa_avx512)
#endif
#if CONTACTNN_KERNELS_NATIVE
CONTACTNN_DECLARE_KERNEL_ISA(isa_native)
#endif

namespace contactnn::search {
namespace {

#define CONTACTNN_KERNEL_ENTRIES(isa, ns)                                           \
  detail::IsaKernels {                                                              \
    isa, &detail::ns::select_bilinear_kernels, &detail::ns::select_gregory_kernels, \
        &detail::ns::network_stages_bilinear, &detail::ns::network_stages_gregory,  \
        &detail::ns::select_face_kernels                                            \
  }

/// The variants this build holds, narrowest first.
const detail::IsaKernels kBuilt[] = {
#if CONTACTNN_KERNELS_BASELINE
    CONTACTNN_KERNEL_ENTRIES(KernelIsa::kBaseline, isa_baseline),
#endif
#if CONTACTNN_KERNELS_AVX2
    CONTACTNN_KERNEL_ENTRIES(KernelIsa::kAvx2, isa_avx2),
#endif
#if CONTACTNN_KERNELS_AVX512
    CONTACTNN_KERNEL_ENTRIES(KernelIsa::kAvx512, isa_avx512),
#endif
#if CONTACTNN_KERNELS_NATIVE
    CONTACTNN_KERNEL_ENTRIES(KernelIsa::kNative, isa_native),
#endif
};
#undef CONTACTNN_KERNEL_ENTRIES

constexpr std::array kAllIsas = {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512,
                                 KernelIsa::kNative};

const detail::IsaKernels* find_built(KernelIsa isa) {
  for (const detail::IsaKernels& k : kBuilt) {
    if (k.isa == isa) return &k;
  }
  return nullptr;
}

std::string built_list() {
  std::string s;
  for (const detail::IsaKernels& k : kBuilt) s += (s.empty() ? "" : ", ") + std::string(to_string(k.isa));
  return s;
}

/// What the CPU and the operating system support (libgcc's or compiler-rt's CPUID reading, which checks that
/// the OS saves the AVX and AVX-512 registers). Read once.
bool cpu_has(KernelIsa isa) {
#if defined(__x86_64__) || defined(__i386__)
  static const bool avx2 = [] {
    __builtin_cpu_init();  // idempotent; needed before the library's constructors have run
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
    return __builtin_cpu_supports("x86-64-v3") != 0;
#else
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
           __builtin_cpu_supports("bmi2");
#endif
  }();
  static const bool avx512 = [] {
    __builtin_cpu_init();
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
    return __builtin_cpu_supports("x86-64-v4") != 0;
#else
    return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl");
#endif
  }();
#else
  constexpr bool avx2 = false, avx512 = false;
#endif
  switch (isa) {
    case KernelIsa::kAvx2: return avx2;
    case KernelIsa::kAvx512: return avx512;
    case KernelIsa::kBaseline:
    case KernelIsa::kNative: return true;  // a native build runs only where it was built
  }
  return false;
}

}  // namespace

std::string_view to_string(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kBaseline: return "baseline";
    case KernelIsa::kAvx2: return "avx2";
    case KernelIsa::kAvx512: return "avx512";
    case KernelIsa::kNative: return "native";
  }
  return "unknown";
}

std::vector<KernelIsa> built_kernel_isas() {
  std::vector<KernelIsa> out;
  for (const detail::IsaKernels& k : kBuilt) out.push_back(k.isa);
  return out;
}

bool cpu_runs(KernelIsa isa) { return find_built(isa) != nullptr && cpu_has(isa); }

KernelIsa kernel_isa() {
  const char* env = std::getenv("CONTACTNN_ISA");
  const std::string_view forced = env != nullptr ? env : "";
  if (!forced.empty() && forced != "auto") {
    for (const KernelIsa isa : kAllIsas) {
      if (forced != to_string(isa)) continue;
      CONTACTNN_REQUIRE_AS(InvalidArgument, find_built(isa) != nullptr,
                           "CONTACTNN_ISA=" << forced
                                            << ": this build of contactnn has no such kernel variant (it has "
                                            << built_list() << ")");
      CONTACTNN_REQUIRE_AS(InvalidArgument, cpu_has(isa),
                           "CONTACTNN_ISA=" << forced << ": this CPU cannot run that kernel variant");
      return isa;
    }
    CONTACTNN_REQUIRE_AS(InvalidArgument, false,
                         "CONTACTNN_ISA=" << forced << ": expected auto or a kernel variant of this build ("
                                          << built_list() << ")");
  }
  KernelIsa best = kBuilt[0].isa;
  for (const detail::IsaKernels& k : kBuilt) {
    if (cpu_has(k.isa)) best = k.isa;
  }
  return best;
}

namespace detail {

const IsaKernels& isa_kernels(KernelIsa isa) {
  const IsaKernels* k = find_built(isa);
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, k != nullptr,
      "no kernel variant " << to_string(isa) << " in this build (it has " << built_list() << ")");
  return *k;
}

}  // namespace detail
}  // namespace contactnn::search
