// The surfaces a parameterised test runs on, and their test names: INSTANTIATE_TEST_SUITE_P(Surfaces, Suite,
// testing::kBothSurfaces, testing::surface_name) gives Surfaces/Suite.Case/bilinear and .../gregory.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/conventions.hpp"

namespace contactnn::testing {

inline const auto kBothSurfaces = ::testing::Values(SurfaceKind::kBilinear, SurfaceKind::kGregory);

/// The test name of a surface parameter: "bilinear", "gregory".
inline std::string surface_name(const ::testing::TestParamInfo<SurfaceKind>& info) {
  return std::string(to_string(info.param));
}

}  // namespace contactnn::testing
