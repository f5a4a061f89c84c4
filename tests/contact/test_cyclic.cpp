// A contact pair between the two cut faces of a cyclic symmetry model (*TIE, CYCLIC SYMMETRY + *CYCLIC
// SYMMETRY MODEL): the slave face of the sector touches the master face of the neighbouring sector, which the
// deck does not mesh. The deck is written here: one twisted annular sector about the x axis whose master
// face, rotated one sector back, lies a small angle delta behind the slave face; every expected foot point
// and gap is computed from that geometry, not by the library.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "contact/scene.hpp"
#include "core/error.hpp"
#include "io/inp_deck.hpp"
#include "scene_checks.hpp"
#include "surface_params.hpp"
#include "test_support.hpp"

namespace contactnn::contact {
namespace {

constexpr int kSectors = 12;
constexpr double kAlpha = 2.0 * std::numbers::pi / kSectors;  // one sector
constexpr double kDelta = 0.01;                               // the gap angle between neighbours' faces
constexpr double kR1 = 2.0, kR2 = 3.0, kLength = 2.0;         // radii and axial length
constexpr int kNr = 3, kNt = 4, kNx = 4;                      // elements along r, theta, x
constexpr double kHx = kLength / kNx;
// The axial twist: the master face's nodes sit 0.37 of an element behind the slave face's (non-matching).
constexpr double kShift = 0.37 * kHx;
constexpr double kTwist = kShift / (kAlpha - kDelta);
// Feet and gaps of flat faces: a few roundings.
constexpr double kTol = 1e-10;

long node_id(int i, int j, int k) { return 1 + i + (kNr + 1) * (j + (kNt + 1) * k); }
long element_id(int i, int j, int k) { return 1 + i + kNr * (j + kNt * k); }

/// World position of the sector's node at radius r, angle theta and axial station x (before the twist).
Vec3 position(double r, double theta, double x) {
  return Vec3(x + kTwist * theta, r * std::cos(theta), r * std::sin(theta));
}

double radius(int i) { return kR1 + (kR2 - kR1) * i / kNr; }
double angle(int j) { return (kAlpha - kDelta) * j / kNt; }

/// The deck: C3D8 elements (local axes r, theta, x: right-handed), Sdep = the theta = 0 faces (S3, 1-5-6-2),
/// Sind = the theta = alpha - delta faces (S5, 3-7-8-4); `cyclic` adds the tie and the model.
std::string sector_deck(bool cyclic) {
  std::ostringstream d;
  d.precision(17);
  d << "*HEADING\ncyclic sector written by test_cyclic\n*NODE, NSET=NALL\n";
  for (int k = 0; k <= kNx; ++k) {
    for (int j = 0; j <= kNt; ++j) {
      for (int i = 0; i <= kNr; ++i) {
        const Vec3 p = position(radius(i), angle(j), kHx * k);
        d << node_id(i, j, k) << ", " << p.x() << ", " << p.y() << ", " << p.z() << "\n";
      }
    }
  }
  d << "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
  for (int k = 0; k < kNx; ++k) {
    for (int j = 0; j < kNt; ++j) {
      for (int i = 0; i < kNr; ++i) {
        d << element_id(i, j, k) << ", " << node_id(i, j, k) << ", " << node_id(i + 1, j, k) << ", "
          << node_id(i + 1, j + 1, k) << ", " << node_id(i, j + 1, k) << ", " << node_id(i, j, k + 1) << ", "
          << node_id(i + 1, j, k + 1) << ", " << node_id(i + 1, j + 1, k + 1) << ", "
          << node_id(i, j + 1, k + 1) << "\n";
      }
    }
  }
  d << "*SURFACE, NAME=Sdep\n";
  for (int k = 0; k < kNx; ++k) {
    for (int i = 0; i < kNr; ++i) d << element_id(i, 0, k) << ", S3\n";
  }
  d << "*SURFACE, NAME=Sind\n";
  for (int k = 0; k < kNx; ++k) {
    for (int i = 0; i < kNr; ++i) d << element_id(i, kNt - 1, k) << ", S5\n";
  }
  if (cyclic) {
    d << "*TIE, NAME=T1, CYCLIC SYMMETRY\nSdep, Sind\n"
      << "*CYCLIC SYMMETRY MODEL, N=" << kSectors
      << ", NGRAPH=1, TIE=T1, CONTACT, ELSET=EALL\n0., 0., 0., 1., 0., 0.\n";
  }
  d << "*CONTACT PAIR, INTERACTION=SI1, TYPE=SURFACE TO SURFACE\nSdep, Sind\n*STEP\n*STATIC\n*END STEP\n";
  return d.str();
}

/// The deck written and read back. ctest -j runs this file's cases as processes of their own at the same
/// time, so each writes its own file (the process id in the name): with one shared name a case once read the
/// deck while another was rewriting it ("the deck has no *CONTACT PAIR", CI).
mesh::ContactModel read_sector(bool cyclic) {
  const auto path = testing::test_output_dir("cyclic") /
                    ((cyclic ? "sector-cyclic-" : "sector-plain-") + std::to_string(::getpid()) + ".inp");
  std::ofstream(path, std::ios::binary) << sector_deck(cyclic);
  mesh::ContactModel model = io::read_inp_deck(path);
  std::filesystem::remove(path);
  return model;
}

/// Bilinear interpolation of the pair's nodes at (xi, eta) in [-1, 1]^2 (A, B, C, D at (-1,-1), (1,-1),
/// (1,1), (-1,1)); the faces are flat parallelograms in (r, x), so the Gregory patch is the same map.
Vec3 point_on(const geometry::Configuration& c, double xi, double eta) {
  const double w[4] = {(1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4, (1 + xi) * (1 + eta) / 4,
                       (1 - xi) * (1 + eta) / 4};
  Vec3 p = Vec3::Zero();
  for (int n = 0; n < 4; ++n) p += w[n] * c.nodes[static_cast<std::size_t>(n)];
  return p;
}

/// move_scene (a run's states, history::RunStates): the deck's scene moved to new node positions is the
/// scene make_scene builds from the moved deck, bit for bit, the rotated copies and their normals included.
TEST(CyclicSymmetry, AMovedSceneIsTheSceneOfTheMovedDeck) {
  mesh::ContactModel model = read_sector(true);
  Scene moved = make_scene(model, 0);
  ASSERT_EQ(moved.cyclic_sectors, kSectors);
  ASSERT_EQ(moved.master.node_count(), 3 * moved.sector_nodes);
  for (int n = 0; n < model.mesh.node_count(); ++n) {
    const Vec3 x = model.mesh.position(n);
    model.mesh.set_position(n, x + Vec3(0.01 * x.y(), -0.02 * x.x(), 0.003 * x.z() * x.y()));
  }
  const Scene rebuilt = make_scene(model, 0);
  std::vector<Vec3> master, slaves;
  for (int j = 0; j < moved.sector_nodes; ++j)
    master.push_back(model.mesh.position(moved.master.mesh_nodes[static_cast<std::size_t>(j)]));
  for (const int n : moved.slaves.nodes) slaves.push_back(model.mesh.position(n));
  move_scene(moved, master, slaves);
  EXPECT_EQ(moved.master.positions, rebuilt.master.positions);
  EXPECT_EQ(moved.master_normals, rebuilt.master_normals);
  EXPECT_EQ(moved.slave_positions, rebuilt.slave_positions);
  EXPECT_EQ(moved.master.segments, rebuilt.master.segments);
  EXPECT_NE(moved.master.positions[0], make_scene(read_sector(true), 0).master.positions[0]);
  EXPECT_THROW(move_scene(moved, std::span<const Vec3>(master).first(master.size() - 1), slaves),
               InvalidArgument);
}

TEST(CyclicSymmetry, TheReaderKeepsTheModelAndItsTie) {
  const mesh::ContactModel model = read_sector(true);
  ASSERT_EQ(model.cyclic.size(), 1u);
  const mesh::CyclicSymmetry& c = model.cyclic[0];
  EXPECT_EQ(c.sectors, kSectors);
  EXPECT_EQ(c.tie, "T1");
  EXPECT_EQ(c.dependent, "Sdep");
  EXPECT_EQ(c.independent, "Sind");
  EXPECT_EQ(c.axis_a, Vec3(0, 0, 0));
  EXPECT_EQ(c.axis_b, Vec3(1, 0, 0));
  EXPECT_TRUE(read_sector(false).cyclic.empty());
}

class CyclicScene : public ::testing::TestWithParam<SurfaceKind> {};

TEST_P(CyclicScene, SlavesFindTheNeighbourSectorsFaceAtTheGapOfTheGeometry) {
  const mesh::ContactModel model = read_sector(true);
  const Scene scene = make_scene(model, 0);
  EXPECT_EQ(scene.cyclic_sectors, kSectors);
  EXPECT_EQ(scene.master.segments.size(), 3u * kNr * kNx);  // the sector's face and two rotated copies
  SearchOptions options;
  options.surface = GetParam();
  options.search = GlobalSearchKind::kNearestNode;
  const SceneResult result = search_scene(scene, options);
  ASSERT_EQ(result.pairs.size(), static_cast<std::size_t>((kNr + 1) * (kNx + 1)));
  int inside = 0, outside = 0;
  for (std::size_t n = 0; n < result.pairs.size(); ++n) {
    const NodeSegmentPair& p = result.pairs[n];
    const Vec3 s = scene.slave_positions[n];
    ASSERT_NEAR(s.z(), 0.0, 1e-14);  // a slave of the theta = 0 face
    const double r = s.y(), x = s.x();
    // The neighbour's face is the plane at angle -delta through the axis: the foot of S is at radius
    // r cos(delta) in that plane, at the same x, and the gap is r sin(delta) (its outward normal faces S).
    const Vec3 foot(x, r * std::cos(kDelta) * std::cos(kDelta), -r * std::cos(kDelta) * std::sin(kDelta));
    const double foot_r = r * std::cos(kDelta);
    const double margin = 0.01 * kHx;
    const bool clearly_in = foot_r > kR1 + margin && foot_r < kR2 - margin && x > kShift + margin &&
                            x < kLength + kShift - margin;
    const bool clearly_out = x < kShift - margin || x > kLength + kShift + margin;
    if (clearly_in) {
      ++inside;
      ASSERT_EQ(p.status, PairStatus::kFound) << "slave " << p.slave_id;
      ASSERT_EQ(p.label.status, Status::kOk) << "slave " << p.slave_id;
      const bool gregory = GetParam() == SurfaceKind::kGregory;
      const double xi = gregory ? 2.0 * p.label.param[0] - 1.0 : p.label.param[0];
      const double eta = gregory ? 2.0 * p.label.param[1] - 1.0 : p.label.param[1];
      EXPECT_LT((point_on(p.config, xi, eta) - foot).norm(), kTol) << "slave " << p.slave_id;
      EXPECT_NEAR(p.label.gap, r * std::sin(kDelta), kTol) << "slave " << p.slave_id;
    } else if (clearly_out) {
      ++outside;
      EXPECT_EQ(p.status, PairStatus::kNoSegment) << "slave " << p.slave_id;
    }
  }
  // The twist leaves the first axial row of slaves beyond the master face; the geometry has both kinds.
  EXPECT_GE(inside, 8);
  EXPECT_GE(outside, 3);
  // The k-d tree over the three copies' nodes (node ids repeated) agrees with the brute-force search.
  options.nearest = NearestNodeMethod::kBruteForce;
  const auto c = testing::compare_searches(result.pairs, search_scene(scene, options).pairs);
  EXPECT_EQ(c.differences, 0) << c.first;
}

TEST_P(CyclicScene, WithoutTheCyclicModelTheSameSlavesOnlySeeTheirOwnSectorsFarFace) {
  const Scene scene = make_scene(read_sector(false), 0);
  EXPECT_EQ(scene.cyclic_sectors, 0);
  EXPECT_EQ(scene.master.segments.size(), static_cast<std::size_t>(kNr * kNx));
  SearchOptions options;
  options.surface = GetParam();
  options.search = GlobalSearchKind::kNearestNode;
  for (const NodeSegmentPair& p : search_scene(scene, options).pairs) {
    // The sector's own master face is alpha - delta away: no pair is a contact at the small gap.
    if (p.status == PairStatus::kFound) {
      EXPECT_GT(std::fabs(p.label.gap), 10.0 * kR2 * std::sin(kDelta));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Surfaces, CyclicScene, testing::kBothSurfaces, testing::surface_name);

}  // namespace
}  // namespace contactnn::contact
