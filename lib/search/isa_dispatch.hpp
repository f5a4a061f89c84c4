// The instruction-set variants of lib/search's kernels. The library itself is compiled for any x86-64 (or,
// with CONTACTNN_NATIVE, for the build machine's CPU); the block and one-lane kernels (kernels_bilinear.cpp,
// kernels_gregory.cpp, kernels_single.cpp) are compiled once per variant (lib/search/CMakeLists.txt), each
// with its symbols to itself (cmake/contactnnIsolateObjects.cmake), and a LocalSearch takes all its kernels
// from one variant, chosen at construction: so a query alone (the one-lane kernel) and in a block give the
// same bits.
//
// The variants with FMA (avx2, avx512, and native on such a CPU) contract a * b + c into one fused
// multiply-add, as GCC does by default, and give the same bits as each other; baseline rounds the product and
// the sum apart, so its results differ from theirs in the last bits (tests/search/test_kernel_isa.cpp
// compares them). Without contraction every variant would agree, but newton:5 ran 1.8-2.4x slower on AVX-512.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace contactnn::search {

class NetworkModel;

/// A variant of the kernels: baseline (any x86-64, SSE2), avx2 (x86-64-v3: AVX2, FMA, BMI2), avx512
/// (x86-64-v4: AVX-512 F, BW, CD, DQ, VL), native (a CONTACTNN_NATIVE build's only variant: the build
/// machine's).
enum class KernelIsa { kBaseline, kAvx2, kAvx512, kNative };

/// "baseline", "avx2", "avx512", "native".
[[nodiscard]] std::string_view to_string(KernelIsa isa);

/// The variants this build holds, narrowest first.
[[nodiscard]] std::vector<KernelIsa> built_kernel_isas();

/// Whether this CPU, and the operating system, run `isa` (native: whether this build holds it).
[[nodiscard]] bool cpu_runs(KernelIsa isa);

/// The variant a LocalSearch constructed now takes: the one the environment variable CONTACTNN_ISA names
/// (baseline, avx2, avx512 or native; unset, empty or "auto": the choice below), else the widest this build
/// holds and this CPU runs. Throws InvalidArgument when CONTACTNN_ISA names no variant, one this build lacks
/// or one this CPU cannot run. For tests and diagnosis (valgrind, which has no AVX-512; a comparison of
/// variants on one machine): an FE code needs nothing here.
[[nodiscard]] KernelIsa kernel_isa();

}  // namespace contactnn::search

namespace contactnn::search::detail {

struct Plan;
struct FacePlan;

/// One variant's entry points (the functions of kernels_bilinear.cpp and kernels_gregory.cpp, in namespace
/// detail::isa_<name>).
struct IsaKernels {
  KernelIsa isa;
  /// Fills plan.block_size and the kernels for plan.kind (bilinear or Gregory).
  void (*select_bilinear)(Plan& plan);
  void (*select_gregory)(Plan& plan);
  /// network_stages (search_plan.hpp) on bilinear and Gregory networks.
  double (*network_stages_bilinear)(const NetworkModel& model, const double* raw, std::size_t count,
                                    int stage, std::size_t& done);
  double (*network_stages_gregory)(const NetworkModel& model, const double* raw, std::size_t count, int stage,
                                   std::size_t& done);
  /// Fills plan.block_size and FaceSearch's kernels for plan.kind (face_kernels.cpp).
  void (*select_face)(FacePlan& plan);
};

/// The entry points of `isa` (one this build holds: see built_kernel_isas).
[[nodiscard]] const IsaKernels& isa_kernels(KernelIsa isa);

}  // namespace contactnn::search::detail

/// Declares the entry points of the variant in namespace contactnn::search::detail::ns (ns = isa_<name>, the
/// compile definition CONTACTNN_KERNEL_ISA of its kernel files; isa_dispatch.cpp declares every variant).
#define CONTACTNN_DECLARE_KERNEL_ISA(ns)                                                                     \
  namespace contactnn::search::detail::ns {                                                                  \
  void select_bilinear_kernels(Plan& plan);                                                                  \
  void select_gregory_kernels(Plan& plan);                                                                   \
  double network_stages_bilinear(const NetworkModel& model, const double* raw, std::size_t count, int stage, \
                                 std::size_t& done);                                                         \
  double network_stages_gregory(const NetworkModel& model, const double* raw, std::size_t count, int stage,  \
                                std::size_t& done);                                                          \
  void select_face_kernels(FacePlan& plan);                                                                  \
  }
