// Tests of lib/core/symmetry.hpp: the 8 symmetries of the square as node relabellings and as maps of
// local coordinates (SPEC 4).
#include <gtest/gtest.h>

#include <set>

#include "core/symmetry.hpp"

namespace contactnn {
namespace {

// The bilinear corners of SPEC 1, written out: A, B, C, D.
constexpr std::array<std::array<double, 2>, 4> kCorners = {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};

TEST(SquareSymmetry, EachOfTheEightIsADistinctRelabelling) {
  std::set<std::array<int, 4>> orders;
  for (const SquareSymmetry& s : all_square_symmetries()) {
    std::array<int, 4> order{};
    std::set<int> used;
    for (int i = 0; i < 4; ++i) {
      order[static_cast<std::size_t>(i)] = s.caller_node(i);
      used.insert(s.caller_node(i));
    }
    EXPECT_EQ(used.size(), 4u) << "not a permutation";
    orders.insert(order);
  }
  EXPECT_EQ(orders.size(), 8u);
}

TEST(SquareSymmetry, KnownOrdersWrittenOut) {
  // rotation 1: canonical A, B, C, D are the caller's B, C, D, A.
  const SquareSymmetry r1{1, false};
  EXPECT_EQ(r1.caller_node(0), 1);
  EXPECT_EQ(r1.caller_node(1), 2);
  EXPECT_EQ(r1.caller_node(3), 0);
  // mirror alone: canonical A, B, C, D are the caller's A, D, C, B.
  const SquareSymmetry m{0, true};
  EXPECT_EQ(m.caller_node(0), 0);
  EXPECT_EQ(m.caller_node(1), 3);
  EXPECT_EQ(m.caller_node(2), 2);
  EXPECT_EQ(m.caller_node(3), 1);
  // One cyclic step maps (xi, eta) to (-eta, xi) (SPEC 4); the mirror swaps the two.
  const auto p = r1.to_caller({0.25, -0.5}, SurfaceKind::kBilinear);
  EXPECT_EQ(p[0], 0.5);
  EXPECT_EQ(p[1], 0.25);
  const auto q = m.to_caller({0.25, -0.5}, SurfaceKind::kBilinear);
  EXPECT_EQ(q[0], -0.5);
  EXPECT_EQ(q[1], 0.25);
}

TEST(SquareSymmetry, CanonicalCornerIMapsToTheCallersCornerOfThatNode) {
  for (const SquareSymmetry& s : all_square_symmetries()) {
    for (int i = 0; i < 4; ++i) {
      const auto& corner = kCorners[static_cast<std::size_t>(i)];
      const auto caller = s.to_caller(corner, SurfaceKind::kBilinear);
      EXPECT_EQ(caller, kCorners[static_cast<std::size_t>(s.caller_node(i))])
          << "rotation " << s.rotation << " mirror " << s.mirror;
      // Gregory: the same in (u, v) = ((xi + 1) / 2, (eta + 1) / 2).
      const auto g = s.to_caller({(corner[0] + 1) / 2, (corner[1] + 1) / 2}, SurfaceKind::kGregory);
      const auto& expected = kCorners[static_cast<std::size_t>(s.caller_node(i))];
      EXPECT_EQ(g[0], (expected[0] + 1) / 2);
      EXPECT_EQ(g[1], (expected[1] + 1) / 2);
    }
  }
}

TEST(SquareSymmetry, ToCanonicalInvertsToCallerExactly) {
  for (const SquareSymmetry& s : all_square_symmetries()) {
    for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
      for (const std::array<double, 2> p : {std::array<double, 2>{0.3, -0.7}, {0.125, 0.875}, {-3.0, 2.5}}) {
        // Bilinear: sign changes and swaps only, exact. Gregory: u -> 1 - u rounds in the last bit.
        const double tol = kind == SurfaceKind::kBilinear ? 0.0 : 4e-16;
        const auto back = s.to_canonical(s.to_caller(p, kind), kind);
        const auto forth = s.to_caller(s.to_canonical(p, kind), kind);
        for (int i = 0; i < 2; ++i) {
          EXPECT_NEAR(back[i], p[i], tol);
          EXPECT_NEAR(forth[i], p[i], tol);
        }
      }
    }
  }
}

TEST(SquareSymmetry, OnlyTheMirrorReversesOrientation) {
  for (const SquareSymmetry& s : all_square_symmetries()) {
    // The Jacobian of to_caller: its determinant is the orientation.
    const auto o = s.to_caller({0, 0}, SurfaceKind::kBilinear);
    const auto x = s.to_caller({1, 0}, SurfaceKind::kBilinear);
    const auto y = s.to_caller({0, 1}, SurfaceKind::kBilinear);
    const double det = (x[0] - o[0]) * (y[1] - o[1]) - (x[1] - o[1]) * (y[0] - o[0]);
    EXPECT_EQ(det, s.orientation());
  }
}

}  // namespace
}  // namespace contactnn
