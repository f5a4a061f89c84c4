// contact::ContactSearch, the handle an FE code calls (issue 38): on every example deck and history deck of
// scripts/make-scene (the example_scenes and example_histories fixtures), moved through increments, its
// answers against surface_search on the deck's own surface; node ids 0-based, 1-based and arbitrary; free
// points; the same bits at 1 and 2 threads and with or without tracking; a mixed flat surface of every face
// type against the plane's known answers; and every bad input refused with the caller's arrays untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/scene.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "io/inp_deck.hpp"

namespace contactnn::contact {
namespace {

constexpr int kFound = static_cast<int>(Status::kOk);
constexpr int kNone = static_cast<int>(Status::kNoSegment);

/// The handle's answers, in arrays as an FE code holds them.
struct Answers : ContactAnswers {
  explicit Answers(std::size_t m, double fill = 0.0) : ContactAnswers(m, -7, -7, fill) {}
};

/// A deck's scene in the handle's terms: every node of the pair (master surface and slave nodes) in
/// increasing deck id, the faces in increasing (element id, face number) (SPEC 9's tie order), their
/// connectivity in deck ids.
struct HandleInput {
  std::vector<long> ids;              ///< deck id of each node of the coordinate array
  std::vector<mesh::FaceType> types;  ///< the caller's faces
  std::vector<long> connectivity;     ///< deck ids
  std::vector<int> deck_face;         ///< the deck surface's face index of caller face i
  std::vector<int> caller_face;       ///< the caller's index of deck face f
};

HandleInput handle_input(const Scene& scene) {
  HandleInput in;
  in.ids = scene.master.node_ids;
  in.ids.insert(in.ids.end(), scene.slave_ids.begin(), scene.slave_ids.end());
  std::sort(in.ids.begin(), in.ids.end());
  in.ids.erase(std::unique(in.ids.begin(), in.ids.end()), in.ids.end());
  const int n = scene.master.face_count();
  in.deck_face = master_faces_in_deck_order(scene);
  in.caller_face.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const int f = in.deck_face[static_cast<std::size_t>(i)];
    in.caller_face[static_cast<std::size_t>(f)] = i;
    const mesh::FaceNodes nodes = scene.master.face_nodes(f);
    in.types.push_back(nodes.type);
    for (int k : nodes) in.connectivity.push_back(scene.master.node_ids[static_cast<std::size_t>(k)]);
  }
  return in;
}

/// The coordinate array of a state: the master's and the slaves' positions by deck id.
std::vector<double> coordinates(const HandleInput& in, const Scene& scene) {
  std::vector<double> x(3 * in.ids.size(), std::numeric_limits<double>::quiet_NaN());
  const auto put = [&](long id, const Vec3& p) {
    const auto i =
        static_cast<std::size_t>(std::lower_bound(in.ids.begin(), in.ids.end(), id) - in.ids.begin());
    for (std::size_t k = 0; k < 3; ++k) x[3 * i + k] = p[static_cast<Eigen::Index>(k)];
  };
  for (std::size_t i = 0; i < scene.master.node_ids.size(); ++i)
    put(scene.master.node_ids[i], scene.master.positions[i]);
  for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) put(scene.slave_ids[i], scene.slave_positions[i]);
  return x;
}

/// An increment of a made-up history: the slave side moves toward and along the master (a rigid translation
/// of up to a fifth of the capture distance per increment), the master surface waves by a small smooth
/// displacement. Deck ids decide nothing: every node of the same kind moves alike.
void move(Scene& scene, int increment, double size) {
  const double t = 0.05 * size * increment;
  for (Vec3& x : scene.master.positions) {
    x += Vec3(0.0, 0.0, 0.02 * size * std::sin(0.7 * increment + x.x() / size) * std::cos(x.y() / size));
  }
  for (Vec3& x : scene.slave_positions) x += Vec3(0.6 * t, 0.3 * t, -0.2 * t);
  scene.master_normals = mesh::node_normals(scene.master);
}

double largest_face(const mesh::SurfaceMesh& m) {
  SearchOptions o;
  return capture_distance(m, o);
}

/// The handle's answers against surface_search's pairs: the same status, face, location; points, parameters
/// and gaps to 1e-10 of the face size; a unit normal with gap = (S - P).n.
void expect_same(const Answers& a, const std::vector<NodeSegmentPair>& pairs, const HandleInput& in,
                 std::span<const Vec3> slaves, double size, const std::string& where) {
  ASSERT_EQ(a.status.size(), pairs.size());
  const double tol = 1e-10 * size;
  long found = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const NodeSegmentPair& p = pairs[i];
    const bool ok = p.status == PairStatus::kFound;
    found += ok;
    ASSERT_EQ(a.status[i], ok ? kFound : kNone) << where << " slave " << i;
    if (!ok) {
      EXPECT_EQ(a.face[i], -1);
      continue;
    }
    ASSERT_EQ(a.face[i], in.caller_face[static_cast<std::size_t>(p.segment)]) << where << " slave " << i;
    EXPECT_EQ(a.location[i], static_cast<int>(p.location)) << where << " slave " << i;
    for (std::size_t k = 0; k < 2; ++k)
      EXPECT_NEAR(a.param[2 * i + k], p.face_param[k], 1e-9) << where << " slave " << i;
    Vec3 point, normal;
    for (std::size_t k = 0; k < 3; ++k) {
      point[static_cast<Eigen::Index>(k)] = a.point[3 * i + k];
      normal[static_cast<Eigen::Index>(k)] = a.normal[3 * i + k];
    }
    EXPECT_LE((point - p.point).norm(), tol) << where << " slave " << i;
    EXPECT_NEAR(a.gap[i], p.label.gap, tol) << where << " slave " << i;
    EXPECT_NEAR(normal.norm(), 1.0, 1e-12) << where << " slave " << i;
    EXPECT_NEAR((slaves[i] - point).dot(normal), a.gap[i], 1e-9 * size) << where << " slave " << i;
  }
  EXPECT_GT(found, 0) << where;
}

struct DeckPair {
  std::string dir;  ///< "scenes" or "histories"
  std::string deck;
  int pair;
};

void PrintTo(const DeckPair& p, std::ostream* os) { *os << p.deck << " pair " << p.pair; }

std::filesystem::path deck_path(const DeckPair& p) {
  return std::filesystem::path(p.dir == "scenes" ? CONTACTNN_EXAMPLE_SCENES_DIR
                                                 : CONTACTNN_EXAMPLE_HISTORIES_DIR) /
         p.deck;
}

const std::vector<DeckPair> kDecks = {
    {"scenes", "hertz.inp", 0},          {"scenes", "hertz.inp", 1},
    {"scenes", "cylinders.inp", 0},      {"scenes", "flat.inp", 0},
    {"scenes", "flat.inp", 1},           {"scenes", "forming.inp", 0},
    {"histories", "hertz-slide.inp", 0}, {"histories", "forming-stroke.inp", 0},
    {"histories", "tet-press.inp", 0},   {"histories", "tubes-press.inp", 0}};

class DeckHandle : public ::testing::TestWithParam<std::tuple<DeckPair, SurfaceKind>> {
 protected:
  void SetUp() override {
    const auto& [deck, kind] = GetParam();
    model_ = io::read_inp_deck(deck_path(deck));
    scene_ = make_scene(model_, deck.pair);
    kind_ = kind;
    // The handle makes every quad4 a segment (a Gregory patch under Gregory); a deck's C3D6 quadrilaterals
    // stay bilinear facets. Such decks are compared under bilinear only.
    bool extra_quads = false;
    for (const auto& e : scene_.master.extra_faces) extra_quads = extra_quads || e[3] >= 0;
    if (kind == SurfaceKind::kGregory && extra_quads)
      GTEST_SKIP() << "C3D6 quadrilaterals in the master surface";
    in_ = handle_input(scene_);
    size_ = largest_face(scene_.master);
  }
  [[nodiscard]] std::vector<NodeSegmentPair> reference(const Scene& scene,
                                                       std::span<const Vec3> slaves) const {
    SearchOptions o;
    o.surface = kind_;
    std::vector<long> ids(slaves.size());
    std::iota(ids.begin(), ids.end(), 0L);
    return surface_search(scene.master, scene.master_normals,
                          scene.slave_ids.size() == slaves.size() ? std::span<const long>(scene.slave_ids)
                                                                  : std::span<const long>(ids),
                          slaves, o);
  }
  mesh::ContactModel model_;
  Scene scene_;
  SurfaceKind kind_ = SurfaceKind::kBilinear;
  HandleInput in_;
  double size_ = 0.0;
};

TEST_P(DeckHandle, AnswersAsTheDecksSurfaceSearchThroughAHistoryWithArbitraryIds) {
  ContactSearchOptions options;
  options.quad4 = kind_;
  ContactSearch handle(in_.types, in_.connectivity, {static_cast<long>(in_.ids.size()), 0, in_.ids},
                       {scene_.slave_ids, 0}, options);
  Scene scene = scene_;
  long tracked = 0;
  for (int increment = 0; increment < 6; ++increment) {
    if (increment > 0) move(scene, increment, size_);
    Answers a(scene.slave_ids.size());
    handle.update(coordinates(in_, scene), {}, a.results());
    expect_same(a, reference(scene, scene.slave_positions), in_, scene.slave_positions, size_,
                "increment " + std::to_string(increment));
    tracked += handle.counts().tracked;
  }
  EXPECT_GT(tracked, 0);  // tracking ran (the lists expire as the slaves move on)
}

TEST_P(DeckHandle, ZeroAndOneBasedIdsFreePointsThreadsAndTrackingGiveTheSameBits) {
  // The same nodes renumbered 0 .. n-1 and 1 .. n.
  std::map<long, long> index;
  for (std::size_t i = 0; i < in_.ids.size(); ++i) index[in_.ids[i]] = static_cast<long>(i);
  const auto renumber = [&](std::span<const long> ids, long base) {
    std::vector<long> out;
    for (long id : ids) out.push_back(index.at(id) + base);
    return out;
  };
  const auto n = static_cast<long>(in_.ids.size());
  const auto m = scene_.slave_ids.size();
  std::vector<Answers> runs;
  Scene scene = scene_;
  std::vector<std::unique_ptr<ContactSearch>> handles;
  for (int variant = 0; variant < 5; ++variant) {
    ContactSearchOptions options;
    options.quad4 = kind_;
    options.threads = variant == 3 ? 2 : 1;
    options.tracking = variant != 4;
    const long base = variant == 1 ? 1 : 0;
    if (variant == 2) {
      handles.push_back(std::make_unique<ContactSearch>(in_.types, renumber(in_.connectivity, 0),
                                                        NodeNumbering{n, 0, {}},
                                                        SlavePoints{{}, static_cast<long>(m)}, options));
    } else {
      handles.push_back(std::make_unique<ContactSearch>(
          in_.types, renumber(in_.connectivity, base), NodeNumbering{n, base, {}},
          SlavePoints{renumber(scene_.slave_ids, base), 0}, options));
    }
  }
  for (int increment = 0; increment < 4; ++increment) {
    if (increment > 0) move(scene, increment, size_);
    const std::vector<double> x = coordinates(in_, scene);
    std::vector<double> free;
    for (const Vec3& s : scene.slave_positions) free.insert(free.end(), {s.x(), s.y(), s.z()});
    std::vector<Answers> answers;
    for (std::size_t h = 0; h < handles.size(); ++h) {
      answers.emplace_back(m);
      handles[h]->update(
          x, handles[h]->free_points() ? std::span<const double>(free) : std::span<const double>(),
          answers.back().results());
    }
    // Ids, free points, threads: the same bits. Without tracking: a fresh search's answers, which tracking
    // gives to rounding (its warm Newton runs end on the same points, not on the same bits).
    for (std::size_t h = 1; h + 1 < answers.size(); ++h) {
      EXPECT_TRUE(answers[h] == answers[0]) << "variant " << h << " at increment " << increment;
    }
    const Answers& fresh = answers.back();
    for (std::size_t i = 0; i < m; ++i) {
      ASSERT_EQ(fresh.status[i], answers[0].status[i]) << i;
      ASSERT_EQ(fresh.face[i], answers[0].face[i]) << i;
      ASSERT_EQ(fresh.location[i], answers[0].location[i]) << i;
      EXPECT_NEAR(fresh.gap[i], answers[0].gap[i], 1e-10 * size_) << i;
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(fresh.point[3 * i + k], answers[0].point[3 * i + k], 1e-10 * size_) << i;
        EXPECT_NEAR(fresh.normal[3 * i + k], answers[0].normal[3 * i + k], 1e-8) << i;
      }
    }
  }
}

TEST_P(DeckHandle, FreePointsBetweenTheSlaveNodesAnswerAsTheSurfaceSearch) {
  // Integration points: midpoints of consecutive slave nodes (a surface-to-surface code's points lie on the
  // slave faces, not at the nodes).
  std::vector<Vec3> points;
  for (std::size_t i = 0; i + 1 < scene_.slave_positions.size(); ++i) {
    points.push_back(0.5 * (scene_.slave_positions[i] + scene_.slave_positions[i + 1]));
  }
  ContactSearchOptions options;
  options.quad4 = kind_;
  ContactSearch handle(in_.types, in_.connectivity, {static_cast<long>(in_.ids.size()), 0, in_.ids},
                       {{}, static_cast<long>(points.size())}, options);
  Scene scene = scene_;
  for (int increment = 0; increment < 3; ++increment) {
    if (increment > 0) {
      move(scene, increment, size_);
      for (Vec3& p : points) p += Vec3(0.01 * size_, -0.02 * size_, -0.01 * size_);
    }
    std::vector<double> free;
    for (const Vec3& s : points) free.insert(free.end(), {s.x(), s.y(), s.z()});
    Answers a(points.size());
    handle.update(coordinates(in_, scene), free, a.results());
    expect_same(a, reference(scene, points), in_, points, size_, "increment " + std::to_string(increment));
  }
}

TEST_P(DeckHandle, ThousandsOfFreePointsGiveTheSameBitsAtOneAndTwoThreads) {
  // Enough points that the tracker's and the search's parallel loops run on both threads (the decks' own
  // slave nodes are fewer than the tracker's serial threshold): points scattered about the master's nodes.
  std::vector<double> free;
  std::uint64_t state = 12345;
  const auto uniform = [&] {  // a fixed LCG: the same points on every platform
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
  };
  for (int copy = 0; static_cast<int>(free.size() / 3) < 2100; ++copy) {
    for (const Vec3& x : scene_.master.positions) {
      free.insert(free.end(), {x.x() + 0.8 * size_ * uniform(), x.y() + 0.8 * size_ * uniform(),
                               x.z() + 0.8 * size_ * uniform()});
    }
  }
  const auto m = free.size() / 3;
  std::vector<Answers> answers;
  std::vector<std::unique_ptr<ContactSearch>> handles;
  for (const int threads : {1, 2}) {
    ContactSearchOptions options;
    options.quad4 = kind_;
    options.threads = threads;
    handles.push_back(std::make_unique<ContactSearch>(
        in_.types, in_.connectivity, NodeNumbering{static_cast<long>(in_.ids.size()), 0, in_.ids},
        SlavePoints{{}, static_cast<long>(m)}, options));
  }
  Scene scene = scene_;
  for (int increment = 0; increment < 2; ++increment) {
    if (increment > 0) {
      move(scene, increment, size_);
      for (std::size_t i = 0; i < free.size(); i += 3) free[i] += 0.01 * size_;
    }
    const std::vector<double> x = coordinates(in_, scene);
    Answers one(m), two(m);
    handles[0]->update(x, free, one.results());
    handles[1]->update(x, free, two.results());
    EXPECT_TRUE(one == two) << "increment " << increment;
  }
}

/// "hertz_0_bilinear": the deck, the pair, the quad4 surface.
std::string deck_test_name(const ::testing::TestParamInfo<DeckHandle::ParamType>& param) {
  const DeckPair& deck = std::get<0>(param.param);
  std::string name = deck.deck.substr(0, deck.deck.find('.')) + "_" + std::to_string(deck.pair) +
                     (std::get<1>(param.param) == SurfaceKind::kGregory ? "_gregory" : "_bilinear");
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

INSTANTIATE_TEST_SUITE_P(Decks, DeckHandle,
                         ::testing::Combine(::testing::ValuesIn(kDecks),
                                            ::testing::Values(SurfaceKind::kBilinear, SurfaceKind::kGregory)),
                         deck_test_name);

// A flat surface at z = 0 made of every face type, in a mixed order: a quad4 on [0,1]x[0,1], two tri3 on
// [1,2]x[0,1], a quad8 on [2,4]x[0,1] and three tri6 on [0,2]x[1,2] (mid-side nodes at the edges' middles:
// flat). The plane's known answers: P = S's foot, gap = S's height, normal +z, parameters from the face's own
// map.
struct FlatMixed {
  std::vector<double> x;  ///< node i at x[3i..]
  std::vector<mesh::FaceType> types;
  std::vector<long> connectivity;  ///< 0-based
  long add(double px, double py) {
    x.insert(x.end(), {px, py, 0.0});
    return static_cast<long>(x.size() / 3 - 1);
  }
  FlatMixed() {
    const long a = add(0, 0), b = add(1, 0), c = add(1, 1), d = add(0, 1);
    types.push_back(mesh::FaceType::kQuad4);
    connectivity.insert(connectivity.end(), {a, b, c, d});
    const long e = add(2, 0), f = add(2, 1);
    types.insert(types.end(), {mesh::FaceType::kTri3, mesh::FaceType::kTri3});
    connectivity.insert(connectivity.end(), {b, e, f, b, f, c});
    const long g = add(4, 0), h = add(4, 1), m1 = add(3, 0), m2 = add(4, 0.5), m3 = add(3, 1),
               m4 = add(2, 0.5);
    types.push_back(mesh::FaceType::kQuad8);
    connectivity.insert(connectivity.end(), {e, g, h, f, m1, m2, m3, m4});
    const long i = add(0, 2), j = add(2, 2), k2 = add(0.5, 1.5), k4 = add(0, 1.5), k5 = add(0.5, 1),
               k6 = add(1.5, 1), k7 = add(2, 1.5), k8 = add(1.5, 1.5), k9 = add(1, 2);
    // tri6 (d, c, i): corners, then the middles of d-c, c-i, i-d.
    types.push_back(mesh::FaceType::kTri6);
    connectivity.insert(connectivity.end(), {d, c, i, k5, k2, k4});
    // tri6 (c, f, j) and (c, j, i): with their middles.
    types.push_back(mesh::FaceType::kTri6);
    connectivity.insert(connectivity.end(), {c, f, j, k6, k7, k8});
    types.push_back(mesh::FaceType::kTri6);
    connectivity.insert(connectivity.end(), {c, j, i, k8, k9, k2});
  }
};

TEST(ContactSearchFlat, EveryFaceTypeMixedGivesThePlanesAnswers) {
  const FlatMixed flat;
  const auto n = static_cast<long>(flat.x.size() / 3);
  // Points strictly inside each face's shadow, above and below.
  const std::vector<Vec3> points = {{0.3, 0.6, 0.25}, {1.7, 0.2, -0.05}, {1.2, 0.7, 0.1},  {3.3, 0.4, 0.2},
                                    {0.4, 1.3, -0.1}, {1.8, 1.4, 0.3},   {1.0, 1.8, 0.05}, {2.9, 0.9, -0.02}};
  // Which face holds each, and its expected parameters in the face's own order.
  const std::vector<int> faces = {0, 1, 2, 3, 4, 5, 6, 3};
  std::vector<double> free;
  for (const Vec3& p : points) free.insert(free.end(), {p.x(), p.y(), p.z()});
  for (const long base : {0L, 1L}) {
    std::vector<long> conn = flat.connectivity;
    for (long& id : conn) id += base;
    ContactSearchOptions options;
    options.capture_distance = 0.5;
    ContactSearch handle(flat.types, conn, {n, base, {}}, {{}, static_cast<long>(points.size())}, options);
    Answers a(points.size());
    handle.update(flat.x, free, a.results());
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_EQ(a.status[i], 0) << i;
      EXPECT_EQ(a.face[i], faces[i]) << i;
      EXPECT_EQ(a.location[i], 0) << i;
      EXPECT_NEAR(a.gap[i], points[i].z(), 1e-12) << i;
      EXPECT_NEAR(a.point[3 * i], points[i].x(), 1e-12) << i;
      EXPECT_NEAR(a.point[3 * i + 1], points[i].y(), 1e-12) << i;
      EXPECT_NEAR(a.point[3 * i + 2], 0.0, 1e-12) << i;
      EXPECT_NEAR(a.normal[3 * i + 2], 1.0, 1e-12) << i;
    }
    // The quad4 [0,1]^2 as a bilinear facet: (xi, eta) = (2x - 1, 2y - 1); the quad8 on [2,4]x[0,1]: (x - 3,
    // 2y - 1); the tri3 (b, e, f) = ((1,0), (2,0), (2,1)): r = x - 1 - (y - 0) ... P = b + r (e - b) + s (f -
    // b).
    EXPECT_NEAR(a.param[0], -0.4, 1e-12);
    EXPECT_NEAR(a.param[1], 0.2, 1e-12);
    EXPECT_NEAR(a.param[6], 0.3, 1e-12);
    EXPECT_NEAR(a.param[7], -0.2, 1e-12);
    EXPECT_NEAR(a.param[2], 0.5, 1e-12);  // (1.7, 0.2) = b + 0.5 (e - b) + 0.2 (f - b)
    EXPECT_NEAR(a.param[3], 0.2, 1e-12);
  }
}

TEST(ContactSearchFlat, BadInputIsRefusedAndNothingIsWritten) {
  const FlatMixed flat;
  const auto n = static_cast<long>(flat.x.size() / 3);
  const std::vector<long> slaves = {0, n};  // a corner of the surface, and a node of no face
  // Creation: each refusal for its own reason (the message says which).
  const std::vector<long> corners = {0, 1};
  const auto refused_at_creation = [](const std::string& words, std::span<const mesh::FaceType> types,
                                      std::span<const long> connectivity, const NodeNumbering& nodes,
                                      const SlavePoints& points) {
    try {
      const ContactSearch handle(types, connectivity, nodes, points);
      ADD_FAILURE() << "not refused: " << words;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused_at_creation("which does not exist", flat.types, flat.connectivity, {n - 1, 0, {}}, {corners, 0});
  refused_at_creation("names node 0, which does not exist", flat.types, flat.connectivity, {n, 1, {}},
                      {corners, 0});
  std::vector<long> short_conn(flat.connectivity.begin(), flat.connectivity.end() - 1);
  refused_at_creation("connectivity of", flat.types, short_conn, {n, 0, {}}, {corners, 0});
  std::vector<mesh::FaceType> bad_type = flat.types;
  bad_type[1] = static_cast<mesh::FaceType>(9);
  refused_at_creation("face 1 has type 9", bad_type, flat.connectivity, {n, 0, {}}, {corners, 0});
  std::vector<long> repeated = flat.connectivity;
  repeated[1] = repeated[0];
  refused_at_creation("face 0 names node 0 twice", flat.types, repeated, {n, 0, {}}, {corners, 0});
  refused_at_creation("slave node 0 names node", flat.types, flat.connectivity, {n, 0, {}},
                      {std::vector<long>{n}, 0});
  refused_at_creation("free points", flat.types, flat.connectivity, {n, 0, {}}, {corners, 3});
  refused_at_creation("free points", flat.types, flat.connectivity, {n, 0, {}}, {{}, 0});
  refused_at_creation("no master faces", {}, {}, {n, 0, {}}, {corners, 0});
  {
    ContactSearchOptions too_many;
    too_many.threads = 1025;
    EXPECT_THROW(ContactSearch(flat.types, flat.connectivity, {n, 0, {}}, {corners, 0}, too_many),
                 InvalidArgument);
  }
  std::vector<long> ids(static_cast<std::size_t>(n));
  std::iota(ids.begin(), ids.end(), 100L);
  const std::vector<long> shifted_corners = {100, 101};
  ids[3] = ids[2];
  refused_at_creation("node id 102 given twice", flat.types, flat.connectivity, {n, 0, ids},
                      {shifted_corners, 0});
  std::iota(ids.begin(), ids.end(), 100L);
  refused_at_creation("is not among", flat.types, flat.connectivity, {n, 0, ids}, {shifted_corners, 0});

  // Updates: a sentinel in every array stays.
  ContactSearch handle(flat.types, flat.connectivity, {n + 1, 0, {}}, {slaves, 0});
  std::vector<double> x = flat.x;
  x.insert(x.end(), {0.5, 0.5, 0.1});  // the second slave node above face 0
  const Answers sentinel(2, -12345.0);
  const auto refused = [&](ContactSearch& h, std::span<const double> coords, std::span<const double> free,
                           auto exception) {
    Answers a(static_cast<std::size_t>(h.slave_count()), -12345.0);
    EXPECT_THROW(h.update(coords, free, a.results()), decltype(exception));
    EXPECT_TRUE(a == Answers(static_cast<std::size_t>(h.slave_count()), -12345.0));
  };
  refused(handle, std::span<const double>(x).first(x.size() - 3), {}, InvalidArgument(""));
  const std::vector<double> three = {0.0, 0.0, 0.0};
  refused(handle, x, three, InvalidArgument(""));
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    std::vector<double> y = x;
    y[3 * 2 + 1] = bad;  // a face's node
    refused(handle, y, {}, NumericalError(""));
    y = x;
    y[3 * 0] = bad;  // a slave node (and a face's)
    refused(handle, y, {}, NumericalError(""));
  }
  {
    Answers a(2, -12345.0);
    Answers wrong(3, -12345.0);
    ContactResults r = a.results();
    r.param = wrong.param;  // 6 values for 2 points
    EXPECT_THROW(handle.update(x, {}, r), InvalidArgument);
    EXPECT_TRUE(a == sentinel);
  }
  // After the refusals, a good update answers (and writes).
  Answers a(2, -12345.0);
  handle.update(x, {}, a.results());
  EXPECT_EQ(a.status[1], 0);
  EXPECT_EQ(a.face[1], 0);
  EXPECT_NEAR(a.gap[1], 0.1, 1e-12);
  // A free-point search given no points, or non-finite ones.
  ContactSearch free_handle(flat.types, flat.connectivity, {n + 1, 0, {}}, {{}, 1});
  refused(free_handle, x, {}, InvalidArgument(""));
  Answers b(1, -12345.0);
  const std::vector<double> nan_point = {0.5, std::numeric_limits<double>::quiet_NaN(), 0.1};
  EXPECT_THROW(free_handle.update(x, nan_point, b.results()), NumericalError);
  EXPECT_TRUE(b == Answers(1, -12345.0));
}

}  // namespace
}  // namespace contactnn::contact
