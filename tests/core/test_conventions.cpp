#include <gtest/gtest.h>

#include <iterator>

#include "core/conventions.hpp"
#include "core/error.hpp"

namespace contactnn {

TEST(Conventions, StatusNamesRoundTripAndMatchSpec) {
  // SPEC 2, 6 and 7 spell the statuses exactly so; outside tools parse these strings.
  const char* expected[] = {"ok",      "outside",       "no_convergence", "degenerate",
                            "invalid", "out_of_domain", "no_segment"};
  static_assert(std::size(expected) == kStatusCount);
  for (int i = 0; i < kStatusCount; ++i) {
    const auto status = static_cast<Status>(i);
    EXPECT_EQ(to_string(status), expected[i]);
    ASSERT_TRUE(status_from_string(expected[i]).has_value());
    EXPECT_EQ(*status_from_string(expected[i]), status);
  }
  EXPECT_FALSE(status_from_string("converged").has_value());
}

TEST(Conventions, ParameterDomainsFollowSpecSection1) {
  EXPECT_EQ(param_domain(SurfaceKind::kBilinear).lo, -1.0);
  EXPECT_EQ(param_domain(SurfaceKind::kBilinear).hi, 1.0);
  EXPECT_EQ(param_domain(SurfaceKind::kGregory).lo, 0.0);
  EXPECT_EQ(param_domain(SurfaceKind::kGregory).hi, 1.0);
  EXPECT_EQ(coordinate_names(SurfaceKind::kBilinear)[0], "xi");
  EXPECT_EQ(coordinate_names(SurfaceKind::kGregory)[1], "v");
  EXPECT_EQ(feature_count(SurfaceKind::kBilinear), 8);
  EXPECT_EQ(feature_count(SurfaceKind::kGregory), 16);
}

TEST(Conventions, UnknownSurfaceNameIsRejectedNamingTheChoices) {
  EXPECT_EQ(surface_from_string("gregory"), SurfaceKind::kGregory);
  try {
    (void)surface_from_string("nurbs");
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("nurbs"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bilinear"), std::string::npos);
  }
}

}  // namespace contactnn
