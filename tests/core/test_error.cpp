#include <gtest/gtest.h>

#include "core/error.hpp"

namespace contactnn {

TEST(Error, RequireThrowsWithValuesAndConditionInRelease) {
  const int n = -3;
  try {
    CONTACTNN_REQUIRE(n > 0, "n must be positive, got " << n);
    FAIL() << "REQUIRE did not throw";
  } catch (const InvalidArgument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("got -3"), std::string::npos) << what;
    EXPECT_NE(what.find("n > 0"), std::string::npos) << what;
    EXPECT_EQ(e.exit_code(), 2);
  }
}

TEST(Error, EachSubclassCarriesItsDocumentedExitCode) {
  EXPECT_EQ(FormatError("x").exit_code(), 3);
  EXPECT_EQ(IoError("x").exit_code(), 4);
  EXPECT_EQ(NumericalError("x").exit_code(), 5);
  EXPECT_EQ(Error("x").exit_code(), 1);
  EXPECT_THROW(CONTACTNN_REQUIRE_AS(IoError, false, "disk " << 1), IoError);
}

}  // namespace contactnn
