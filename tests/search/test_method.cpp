// lib/search/method: names parse to the methods they describe and back; malformed names are refused with
// a message listing the accepted forms.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "search/method.hpp"

namespace contactnn::search {
namespace {

using Start = Method::Start;

TEST(Method, ParsesEveryForm) {
  EXPECT_EQ(Method::parse("network"), (Method{Start::kNetwork, 0, false}));
  EXPECT_EQ(Method::parse("newton"), (Method{Start::kCentre, 0, true}));
  EXPECT_EQ(Method::parse("newton:5"), (Method{Start::kCentre, 5, false}));
  EXPECT_EQ(Method::parse("newton:0"), (Method{Start::kCentre, 0, false}));
  EXPECT_EQ(Method::parse("closed_form"), (Method{Start::kClosedForm, 0, false}));
  EXPECT_EQ(Method::parse("network+newton:3"), (Method{Start::kNetwork, 3, false}));
  EXPECT_EQ(Method::parse("closed_form+newton:12"), (Method{Start::kClosedForm, 12, false}));
  EXPECT_EQ(Method::parse("start+newton:2"), (Method{Start::kGiven, 2, false}));
  EXPECT_EQ(Method::parse("start"), (Method{Start::kGiven, 0, false}));
  EXPECT_EQ(Method::parse("four_triangles"), (Method{Start::kFourTriangles, 0, false}));
  // ":0" is the start alone.
  EXPECT_EQ(Method::parse("network+newton:0"), Method::parse("network"));
  EXPECT_EQ(Method::parse("closed_form+newton:0"), Method::parse("closed_form"));
  EXPECT_EQ(Method::parse("start+newton:0"), Method::parse("start"));
}

TEST(Method, NameRoundTrips) {
  for (const char* name :
       {"network", "newton", "newton:0", "newton:1", "newton:10", "closed_form", "network+newton:1",
        "network+newton:3", "closed_form+newton:1", "closed_form+newton:25", "start", "start+newton:3",
        "four_triangles", "newton:1000"}) {
    const Method m = Method::parse(name);
    EXPECT_EQ(m.name(), name);
    EXPECT_EQ(Method::parse(m.name()), m);
  }
  EXPECT_EQ(Method::parse("network+newton:0").name(), "network");
}

TEST(Method, HybridsAndNetworkNeedsAreClassified) {
  EXPECT_TRUE(Method::parse("network").needs_network());
  EXPECT_FALSE(Method::parse("network").is_hybrid());
  EXPECT_TRUE(Method::parse("network+newton:1").is_hybrid());
  EXPECT_TRUE(Method::parse("closed_form+newton:2").is_hybrid());
  EXPECT_FALSE(Method::parse("closed_form+newton:2").needs_network());
  EXPECT_FALSE(Method::parse("newton:5").is_hybrid());
  EXPECT_TRUE(Method::parse("start+newton:3").is_hybrid());
  EXPECT_TRUE(Method::parse("start+newton:3").needs_start());
  EXPECT_FALSE(Method::parse("start+newton:3").needs_network());
  EXPECT_FALSE(Method::parse("network+newton:3").needs_start());
  const Method triangles = Method::parse("four_triangles");
  EXPECT_FALSE(triangles.needs_network());
  EXPECT_FALSE(triangles.needs_start());
  EXPECT_FALSE(triangles.is_hybrid());
  EXPECT_FALSE(triangles.to_convergence);
}

TEST(Method, MalformedNamesAreRefusedNamingTheForms) {
  for (const char* bad : {"",
                          "Network",
                          "newton:",
                          "newton:-1",
                          "newton:x",
                          "newton:3x",
                          "newton: 3",
                          "newton:1.5",
                          "network+newton",
                          "network+newton:",
                          "closed_form+newton:-2",
                          "gauss",
                          "network+",
                          "start+newton",
                          "start+newton:",
                          "start:3",
                          "four_triangles+newton:2",
                          "four_triangles:1",
                          "Four_triangles",
                          "newton:99999999999999999999",
                          "newton:1001",
                          "newton:100000000"}) {
    try {
      (void)Method::parse(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("closed_form+newton:K"), std::string::npos) << e.what();
    }
  }
}

TEST(Method, StepCountsAboveTheLimitAreRefusedInEveryForm) {
  // newton:K took 1.1 s per query at K = 1e8: K is at most Method::kMaxSteps (1000), in every form with K.
  EXPECT_EQ(Method::kMaxSteps, 1000);
  for (const char* form : {"newton:", "network+newton:", "closed_form+newton:", "start+newton:"}) {
    EXPECT_EQ(Method::parse(std::string(form) + "1000").newton_steps, 1000) << form;
    for (const char* k : {"1001", "2000000000"}) {
      const std::string name = std::string(form) + k;
      try {
        (void)Method::parse(name);
        ADD_FAILURE() << "accepted '" << name << "'";
      } catch (const InvalidArgument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("limit of 1000"), std::string::npos) << what;
        EXPECT_NE(what.find(name), std::string::npos) << what;
      }
    }
  }
}

}  // namespace
}  // namespace contactnn::search
