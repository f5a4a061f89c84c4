// contact::ContactSearch with a face-interior method (ContactSearchOptions::method, issue 38: the handle
// takes "method or plan file"): on a warped sheet of curved bilinear (and Gregory) quad4 faces moved through
// increments, the handle's answers, tracked and fresh, are surface_search's with SearchOptions::interior set
// to a FaceLocator of the same method (same faces and locations, points, parameters and gaps to 1e-12), and
// an inexact method's answers differ from the exact search's; a network method with its network; a bad
// method, start+newton:K, a network method without a network, a network without a method and a network of the
// other surface are refused, naming the option.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/narrow_phase.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "io/network_model_file.hpp"
#include "mesh/surface_mesh.hpp"
#include "search/network_model.hpp"

namespace contactnn::contact {
namespace {

constexpr int kCells = 6;  ///< the sheet: kCells x kCells quad4 faces of size ~1
constexpr int kGridNodes = (kCells + 1) * (kCells + 1);  ///< node ids 1 .. kGridNodes, then the slaves
constexpr int kSlaves = 400;

/// The sheet's node (i, j) at increment `inc`: every face a curved (non-planar) bilinear facet, the wave
/// moving from one increment to the next.
Vec3 sheet(int i, int j, int inc) {
  const double x = i, y = j;
  return {x, y, 0.3 * std::sin(1.3 * x + 0.1 * inc) * std::cos(0.9 * y) + 0.05 * x * y};
}

/// Slave k at increment `inc`: spread over the sheet, above and below it, drifting along it.
Vec3 slave(int k, int inc) {
  const double s = 0.5 + 0.5 * std::sin(12.9898 * k), t = 0.5 + 0.5 * std::sin(78.233 * k + 1.0);
  const double h = 0.7 * std::sin(37.719 * k + 2.0);
  return {-0.3 + 6.6 * s + 0.04 * inc, -0.3 + 6.6 * t + 0.02 * inc, h};
}

struct Sheet {
  std::vector<mesh::FaceType> types;
  std::vector<long> connectivity;
  std::vector<long> slave_ids;
};

Sheet make_sheet() {
  Sheet s;
  const auto id = [](int i, int j) { return 1L + i + (kCells + 1L) * j; };
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      s.types.push_back(mesh::FaceType::kQuad4);
      for (const long n : {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)})
        s.connectivity.push_back(n);
    }
  }
  for (int k = 0; k < kSlaves; ++k) s.slave_ids.push_back(kGridNodes + 1L + k);
  return s;
}

std::vector<double> coordinates(int inc) {
  std::vector<double> x;
  for (int j = 0; j <= kCells; ++j) {
    for (int i = 0; i <= kCells; ++i) {
      const Vec3 p = sheet(i, j, inc);
      x.insert(x.end(), {p.x(), p.y(), p.z()});
    }
  }
  for (int k = 0; k < kSlaves; ++k) {
    const Vec3 p = slave(k, inc);
    x.insert(x.end(), {p.x(), p.y(), p.z()});
  }
  return x;
}

struct Answers {
  std::vector<int> status, face, location;
  std::vector<double> param, point, gap, normal;
  explicit Answers(std::size_t m)
      : status(m, -7),
        face(m, -7),
        location(m, -7),
        param(2 * m, 7.0),
        point(3 * m, 7.0),
        gap(m, 7.0),
        normal(3 * m, 7.0) {}
  ContactResults results() { return {status, face, location, param, point, gap, normal}; }
};

ContactSearch make_handle(const Sheet& s, const ContactSearchOptions& o) {
  return ContactSearch(s.types, s.connectivity, {kGridNodes + kSlaves, 1, {}}, {s.slave_ids, 0}, o);
}

/// surface_search on the handle's surface (its positions those of its last update) with `interior`.
std::vector<NodeSegmentPair> direct(const ContactSearch& handle, const Sheet& s, SurfaceKind kind,
                                    const FaceLocator* interior, int inc) {
  SearchOptions o;
  o.surface = kind;
  o.search = GlobalSearchKind::kSurface;
  o.interior = interior;
  std::vector<Vec3> slaves;
  for (int k = 0; k < kSlaves; ++k) slaves.push_back(slave(k, inc));
  const std::vector<Vec3> normals =
      kind == SurfaceKind::kGregory ? mesh::node_normals(handle.surface()) : std::vector<Vec3>{};
  return surface_search(handle.surface(), normals, s.slave_ids, slaves, o);
}

/// The handle's answers are `pairs` (the sheet's faces are the handle's faces in the caller's order).
void expect_same(const Answers& a, const std::vector<NodeSegmentPair>& pairs, const std::string& where) {
  ASSERT_EQ(pairs.size(), a.status.size());
  long found = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const NodeSegmentPair& p = pairs[i];
    const bool ok = p.status == PairStatus::kFound;
    found += ok ? 1 : 0;
    ASSERT_EQ(a.status[i], static_cast<int>(ok ? Status::kOk : Status::kNoSegment)) << where << " " << i;
    ASSERT_EQ(a.face[i], ok ? p.segment : -1) << where << " slave " << i;
    if (!ok) continue;
    EXPECT_EQ(a.location[i], static_cast<int>(p.location)) << where << " slave " << i;
    for (std::size_t k = 0; k < 2; ++k) EXPECT_NEAR(a.param[2 * i + k], p.face_param[k], 1e-12) << where;
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_NEAR(a.point[3 * i + k], p.point[static_cast<Eigen::Index>(k)], 1e-12) << where << " " << i;
    EXPECT_NEAR(a.gap[i], p.label.gap, 1e-12) << where << " slave " << i;
  }
  EXPECT_GT(found, kSlaves / 2) << where;
}

/// How many slave points' points lie more than 1e-8 from the exact search's.
long differing(const Answers& a, const std::vector<NodeSegmentPair>& exact) {
  long n = 0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    if (exact[i].status != PairStatus::kFound) continue;
    const Vec3 p(a.point[3 * i], a.point[3 * i + 1], a.point[3 * i + 2]);
    n += (p - exact[i].point).norm() > 1e-8 ? 1 : 0;
  }
  return n;
}

struct MethodCase {
  SurfaceKind kind;
  std::string method;
};

class ContactSearchMethod : public ::testing::TestWithParam<MethodCase> {};

TEST_P(ContactSearchMethod, AnswersAsTheSurfaceSearchWithItsLocatorTrackedAndFreshAndDiffersFromExact) {
  const auto [kind, method] = GetParam();
  const Sheet s = make_sheet();
  const FaceLocator locator(method);
  for (const bool tracking : {true, false}) {
    ContactSearchOptions o;
    o.quad4 = kind;
    o.method = method;
    o.tracking = tracking;
    o.threads = 2;
    ContactSearch handle = make_handle(s, o);
    long differ = 0;
    for (int inc = 0; inc < 4; ++inc) {
      Answers a(kSlaves);
      handle.update(coordinates(inc), {}, a.results());
      const std::string where = method + " " + std::string(to_string(kind)) +
                                (tracking ? " tracked" : " fresh") + " increment " + std::to_string(inc);
      expect_same(a, direct(handle, s, kind, &locator, inc), where);
      differ += differing(a, direct(handle, s, kind, nullptr, inc));
    }
    // The method is inexact on these curved faces: many face-interior points are not the exact search's.
    EXPECT_GT(differ, 4 * kSlaves / 10) << method << (tracking ? " tracked" : " fresh");
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, ContactSearchMethod,
                         ::testing::Values(MethodCase{SurfaceKind::kBilinear, "newton:1"},
                                           MethodCase{SurfaceKind::kBilinear, "closed_form"},
                                           MethodCase{SurfaceKind::kGregory, "newton:1"}),
                         [](const auto& param_info) {
                           std::string name =
                               std::string(to_string(param_info.param.kind)) + "_" + param_info.param.method;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

TEST(ContactSearchMethodExact, NewtonToConvergenceAndTheEmptyMethodGiveTheExactSearch) {
  const Sheet s = make_sheet();
  ContactSearchOptions exact;
  ContactSearchOptions newton;
  newton.method = "newton";
  ContactSearch a = make_handle(s, exact), b = make_handle(s, newton);
  Answers x(kSlaves), y(kSlaves);
  a.update(coordinates(1), {}, x.results());
  b.update(coordinates(1), {}, y.results());
  expect_same(x, direct(a, s, SurfaceKind::kBilinear, nullptr, 1), "exact");
  EXPECT_EQ(differing(y, direct(b, s, SurfaceKind::kBilinear, nullptr, 1)), 0);
}

TEST(ContactSearchMethodNetwork, ANetworkMethodAnswersAsItsLocatorAndNeedsItsNetworkOfItsSurface) {
  const Sheet s = make_sheet();
  std::shared_ptr<const search::NetworkModel> network =
      io::read_network_model(CONTACTNN_SOURCE_DIR "/data/weights/bilinear-8.h5");
  ContactSearchOptions o;
  o.method = "network+newton:1";
  o.network = network;
  ContactSearch handle = make_handle(s, o);
  Answers a(kSlaves);
  handle.update(coordinates(2), {}, a.results());
  const FaceLocator locator("network+newton:1", network.get());
  expect_same(a, direct(handle, s, SurfaceKind::kBilinear, &locator, 2), "network+newton:1");
  EXPECT_GT(differing(a, direct(handle, s, SurfaceKind::kBilinear, nullptr, 2)), kSlaves / 10);

  o.quad4 = SurfaceKind::kGregory;  // a bilinear network for Gregory faces
  try {
    (void)make_handle(s, o);
    ADD_FAILURE() << "a bilinear network on Gregory quad4 faces was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("bilinear network, options.quad4 is gregory"), std::string::npos)
        << e.what();
  }
}

TEST(ContactSearchMethodErrors, ABadMethodIsRefusedNamingTheOption) {
  const Sheet s = make_sheet();
  const auto refused = [&](const ContactSearchOptions& o, const std::string& expected) {
    try {
      (void)make_handle(s, o);
      ADD_FAILURE() << "method '" << o.method << "' was accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  ContactSearchOptions o;
  o.method = "newton:two";
  refused(o, "contact search: options.method: ");
  refused(o, "'newton:two'");
  o.method = "start+newton:2";
  refused(o, "no start to give it");
  o.method = "network+newton:1";
  refused(o, "needs a network");
  o.method = "";
  o.network = io::read_network_model(CONTACTNN_SOURCE_DIR "/data/weights/bilinear-8.h5");
  refused(o, "a network is given without a method");
}

}  // namespace
}  // namespace contactnn::contact
