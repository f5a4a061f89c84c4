// The arithmetic a method performs per query, for the benchmark's floor: flops per query divided by the
// machine's matrix-product rate (scripts/bench-search; issue 11's "within 3x of its floor").
#pragma once

#include "core/conventions.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"
#include "search/method.hpp"
#include "search/network_model.hpp"

namespace contactnn::search {

/// Floating-point operations per query, split by precision (the floor divides each by the GEMM rate of its
/// own type). Counted from the kernels of lib/search as written (flop_count.cpp itemises them): an add,
/// subtract, multiply, divide or square root is 1, a fused multiply-add 2 (a matrix product's convention);
/// comparisons, min/max, absolute values, selects, conversions and loads/stores are not counted, so the floor
/// is a lower bound on arithmetic alone, and divisions and square roots, several times slower than a
/// multiply-add, count as one each: a method heavy in either sits further above its floor.
struct FlopCount {
  double in_double = 0.0;
  double in_float = 0.0;
  [[nodiscard]] double total() const { return in_double + in_float; }
};

/// `newton_steps`: Newton steps per query for "newton" (to convergence), whose count depends on the data
/// (the benchmark passes the measured mean); ignored otherwise. The gap is not included (its cost: one
/// surface evaluation per query). InvalidArgument for a network method without `network` and for
/// four_triangles on Gregory segments.
[[nodiscard]] FlopCount flops_per_query(SurfaceKind kind, const Method& method, const NetworkModel* network,
                                        double newton_steps = 0.0);

/// The same for FaceSearch (face_block.hpp, face_network_block.hpp): `newton_steps` as above, for "newton".
/// InvalidArgument for a network method without `network`.
[[nodiscard]] FlopCount face_flops_per_query(FaceKind kind, const Method& method, const FaceNetwork* network,
                                             double newton_steps = 0.0);

}  // namespace contactnn::search
