#include "study/face_study.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>

#include "contact/global_search.hpp"
#include "core/error.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "mlp/scaling.hpp"
#include "mlp/trainer.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"
#include "search/method.hpp"
#include "study/scene_domain.hpp"

namespace contactnn::study {

using geometry::Vec3;
using search::FaceKind;

namespace {

mesh::FaceType mesh_type(FaceKind kind) {
  return kind == FaceKind::kQuad8 ? mesh::FaceType::kQuad8
                                  : (kind == FaceKind::kTri6 ? mesh::FaceType::kTri6 : mesh::FaceType::kTri3);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The nodes of face f in SPEC 9's order.
std::vector<Vec3> face_positions(const mesh::SurfaceMesh& m, int f) {
  const mesh::FaceNodes n = m.face_nodes(f);
  std::vector<Vec3> x;
  for (const int i : n) x.push_back(m.positions[static_cast<std::size_t>(i)]);
  return x;
}

double shortest_corner_edge(const std::vector<Vec3>& x, int corners) {
  double e = std::numeric_limits<double>::infinity();
  for (int i = 0; i < corners; ++i)
    e = std::min(e, (x[static_cast<std::size_t>((i + 1) % corners)] - x[static_cast<std::size_t>(i)]).norm());
  return e;
}

/// The closest point on the true face (interior, edges, vertices).
projection::FaceClosestPoint closest(FaceKind kind, const std::vector<Vec3>& x, const Vec3& s) {
  if (kind == FaceKind::kQuad8) {
    std::array<Vec3, 8> n;
    std::copy(x.begin(), x.begin() + 8, n.begin());
    return projection::closest_point_on_serendipity_quad(geometry::SerendipityQuad(n), s);
  }
  std::array<Vec3, 6> n;
  std::copy(x.begin(), x.begin() + 6, n.begin());
  return projection::closest_point_on_quadratic_triangle(geometry::QuadraticTriangle(n), s);
}

geometry::SurfacePoint evaluate(FaceKind kind, const std::vector<Vec3>& x, double s, double t) {
  if (kind == FaceKind::kQuad8) {
    std::array<Vec3, 8> n;
    std::copy(x.begin(), x.begin() + 8, n.begin());
    return geometry::SerendipityQuad(n).evaluate(s, t);
  }
  std::array<Vec3, 6> n;
  std::copy(x.begin(), x.begin() + 6, n.begin());
  return geometry::QuadraticTriangle(n).evaluate(s, t);
}

void append(std::vector<double>& raw, const std::vector<Vec3>& nodes, const Vec3& s) {
  for (const Vec3& p : nodes) raw.insert(raw.end(), {p.x(), p.y(), p.z()});
  raw.insert(raw.end(), {s.x(), s.y(), s.z()});
}

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

std::string size_name(int inputs, const std::vector<int>& hidden) {
  std::string s = std::to_string(inputs);
  for (const int h : hidden) s += "-" + std::to_string(h);
  return s + "-2";
}

/// The larger coordinate's mean |error| of `param` against `label` over the rows answered (status ok, or a
/// network's out_of_domain estimate); failures (any other status: every label lies inside its face, so an
/// answer outside is wrong too) counted apart; the max.
struct Errors {
  double mean = 0.0, max = 0.0;
  long failures = 0;
};

Errors errors_of(const std::vector<double>& param, const std::vector<Status>& status, const FaceQueries& q) {
  double sum[2] = {0.0, 0.0};
  Errors e;
  long counted = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const bool answered = status[i] == Status::kOk || status[i] == Status::kOutOfDomain;
    if (!answered) {
      ++e.failures;
      continue;
    }
    for (int k = 0; k < 2; ++k) {
      const double d = std::fabs(param[2 * i + static_cast<std::size_t>(k)] -
                                 q.label[2 * i + static_cast<std::size_t>(k)]);
      sum[k] += d;
      e.max = std::max(e.max, d);
    }
    ++counted;
  }
  e.mean = counted > 0 ? std::max(sum[0], sum[1]) / static_cast<double>(counted) : 0.0;
  return e;
}

/// Runs `search` over q (starts: none), into param and status.
void run_search(const search::FaceSearch& search, const FaceQueries& q, std::vector<double>& param,
                std::vector<Status>& status, int threads) {
  param.assign(2 * q.size(), 0.0);
  status.assign(q.size(), Status::kOk);
  search.run<double>(q.size(), q.raw.data(), search::Results<double>{param.data(), nullptr, status.data()},
                     threads);
}

}  // namespace

FacePairs face_pairs(const contact::Scene& scene, FaceKind kind) {
  contact::SearchOptions options;
  options.search = contact::GlobalSearchKind::kSurface;
  const contact::SceneResult result = contact::search_scene(scene, options);
  FacePairs out;
  out.pairs.kind = kind;
  out.slave_nodes = static_cast<long>(result.pairs.size());
  const mesh::FaceType type = mesh_type(kind);
  for (int f = 0; f < scene.master.face_count(); ++f) out.faces += scene.master.face_type(f) == type;
  for (std::size_t i = 0; i < result.pairs.size(); ++i) {
    const contact::NodeSegmentPair& p = result.pairs[i];
    if (p.status != contact::PairStatus::kFound || scene.master.face_type(p.segment) != type) continue;
    ++out.on_kind;
    if (p.location != Location::kFace) continue;
    const std::vector<Vec3> x = face_positions(scene.master, p.segment);
    append(out.pairs.raw, x, scene.slave_positions[i]);
    out.pairs.label.insert(out.pairs.label.end(), {p.face_param[0], p.face_param[1]});
    out.slave_ids.push_back(p.slave_id);
    const int corners = kind == FaceKind::kQuad8 ? 4 : 3;
    const double distance = (scene.slave_positions[i] - p.point).norm();
    out.largest_offset = std::max(out.largest_offset, distance / shortest_corner_edge(x, corners));
  }
  return out;
}

namespace {

/// A foot point of a face in its parameters: uniform over the quad's square or the triangle, or
/// (boundary_fraction) half of the time on a node, half on an edge.
std::array<double, 2> draw_foot(int corners, double boundary_fraction, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double s, t;
  const double where = unit(rng);
  if (corners == 4) {
    s = 2.0 * unit(rng) - 1.0;
    t = 2.0 * unit(rng) - 1.0;
    if (where < 0.5 * boundary_fraction) {  // a node
      s = s < 0.0 ? -1.0 : 1.0;
      t = t < 0.0 ? -1.0 : 1.0;
    } else if (where < boundary_fraction) {  // an edge
      (unit(rng) < 0.5 ? s : t) = unit(rng) < 0.5 ? -1.0 : 1.0;
    }
  } else {
    do {
      s = unit(rng);
      t = unit(rng);
    } while (s + t > 1.0);
    if (where < 0.5 * boundary_fraction) {
      const int node = static_cast<int>(3.0 * unit(rng)) % 3;
      s = node == 1 ? 1.0 : 0.0;
      t = node == 2 ? 1.0 : 0.0;
    } else if (where < boundary_fraction) {
      const int edge = static_cast<int>(3.0 * unit(rng)) % 3;
      const double a = unit(rng);
      s = edge == 0 ? a : (edge == 1 ? 1.0 - a : 0.0);
      t = edge == 0 ? 0.0 : (edge == 1 ? a : 1.0 - a);
    }
  }
  return {s, t};
}

/// `count` rows: each draws from the generator of (seed, row) a face (`draw_face(rng, nodes)` fills its nodes
/// and returns the slave's largest offset along the normal) and a foot point, places S over it, labels it by
/// the closest point on the true face and keeps it when that lies inside; up to 1000 draws a row, rows that
/// kept none dropped (none on the decks tried). Any thread count gives the same set.
template <class DrawFace>
FaceQueries sample_rows(FaceKind kind, const FaceStudyOptions& options, std::int64_t count,
                        std::uint64_t seed, std::uint64_t stream, const DrawFace& draw_face) {
  const int corners = kind == FaceKind::kQuad8 ? 4 : 3;
  FaceQueries out;
  out.kind = kind;
  const int stride = search::face_raw_columns(kind);
  out.raw.assign(static_cast<std::size_t>(count) * static_cast<std::size_t>(stride), 0.0);
  out.label.assign(2 * static_cast<std::size_t>(count), 0.0);
  std::vector<char> kept(static_cast<std::size_t>(count), 0);
#pragma omp parallel for schedule(dynamic, 256) \
    num_threads(options.threads > 0 ? options.threads : omp_get_max_threads())
  for (std::int64_t row = 0; row < count; ++row) {
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL +
                        static_cast<std::uint64_t>(row) * 0xBF58476D1CE4E5B9ULL + stream);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3> x;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const double offset = draw_face(rng, x);
      const auto [s, t] = draw_foot(corners, options.boundary_fraction, rng);
      const geometry::SurfacePoint p = evaluate(kind, x, s, t);
      const Vec3 n = p.d_s.cross(p.d_t).normalized();
      const Vec3 slave = p.position + (2.0 * unit(rng) - 1.0) * offset * n;
      const projection::FaceClosestPoint c = closest(kind, x, slave);
      if (c.status != Status::kOk || c.location != Location::kFace) continue;
      double* r = out.raw.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(stride);
      for (std::size_t i = 0; i < x.size(); ++i) {
        for (int k = 0; k < 3; ++k) r[3 * i + static_cast<std::size_t>(k)] = x[i][k];
      }
      for (int k = 0; k < 3; ++k) r[3 * x.size() + static_cast<std::size_t>(k)] = slave[k];
      out.label[2 * static_cast<std::size_t>(row)] = c.param[0];
      out.label[2 * static_cast<std::size_t>(row) + 1] = c.param[1];
      kept[static_cast<std::size_t>(row)] = 1;
      break;
    }
  }
  std::size_t to = 0;
  for (std::size_t row = 0; row < kept.size(); ++row) {
    if (!kept[row]) continue;
    std::copy_n(out.raw.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(stride)), stride,
                out.raw.begin() + static_cast<std::ptrdiff_t>(to * static_cast<std::size_t>(stride)));
    out.label[2 * to] = out.label[2 * row];
    out.label[2 * to + 1] = out.label[2 * row + 1];
    ++to;
  }
  out.raw.resize(to * static_cast<std::size_t>(stride));
  out.label.resize(2 * to);
  return out;
}

}  // namespace

FaceQueries sample_face_domain(const contact::Scene& scene, FaceKind kind, const FaceStudyOptions& options,
                               double capture, std::int64_t count, std::uint64_t seed) {
  const mesh::FaceType type = mesh_type(kind);
  const int corners = kind == FaceKind::kQuad8 ? 4 : 3;
  std::vector<std::vector<Vec3>> faces;
  std::vector<double> cumulative;  // area weights (the corner facet's)
  double total = 0.0;
  for (int f = 0; f < scene.master.face_count(); ++f) {
    if (scene.master.face_type(f) != type) continue;
    std::vector<Vec3> x = face_positions(scene.master, f);
    const double area = corners == 4 ? 0.5 * (x[2] - x[0]).cross(x[3] - x[1]).norm()
                                     : 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
    total += area;
    cumulative.push_back(total);
    faces.push_back(std::move(x));
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, !faces.empty() && total > 0.0,
                       "the master surface has no " << search::to_string(kind) << " face of positive area");
  return sample_rows(kind, options, count, seed, 1, [&](std::mt19937_64& rng, std::vector<Vec3>& x) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double pick = unit(rng) * total;
    const auto f = static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), pick) -
                                            cumulative.begin());
    x = faces[std::min(f, faces.size() - 1)];
    const double e = shortest_corner_edge(x, corners);
    for (Vec3& p : x) {
      Vec3 d;
      do {
        d = Vec3(2.0 * unit(rng) - 1.0, 2.0 * unit(rng) - 1.0, 2.0 * unit(rng) - 1.0);
      } while (d.squaredNorm() > 1.0);
      p += options.deformation * e * d;
    }
    return capture * e;
  });
}

FaceQueries sample_general_face_domain(FaceKind kind, const FaceStudyOptions& options, double curvature,
                                       std::int64_t count, std::uint64_t seed) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, kind != FaceKind::kTri3, "tri3 faces have no network domain");
  const int corners = kind == FaceKind::kQuad8 ? 4 : 3;
  return sample_rows(kind, options, count, seed, 7, [&](std::mt19937_64& rng, std::vector<Vec3>& x) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto in = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    const double angle = in(60.0, 120.0) * 3.14159265358979323846 / 180.0, length = in(0.5, 1.0);
    const Vec3 last(length * std::cos(angle), length * std::sin(angle), 0.0);
    x = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    if (corners == 4) x.push_back(Vec3(1, 0, 0) + last + Vec3(in(-0.3, 0.3), in(-0.3, 0.3), in(-0.3, 0.3)));
    x.push_back(last);
    for (int e = 0; e < corners; ++e) {
      const Vec3 a = x[static_cast<std::size_t>(e)];
      const Vec3 b = x[static_cast<std::size_t>((e + 1) % corners)];
      const double r = curvature * (b - a).norm();
      x.push_back(0.5 * (a + b) + Vec3(in(-r, r), in(-r, r), in(-r, r)));
    }
    return 0.3;
  });
}

namespace {

/// Canonical features and targets of `q` (rows without a frame dropped).
void canonical_set(const FaceQueries& q, mlp::MatrixRM<double>& features, mlp::MatrixRM<double>& targets) {
  const int nf = search::face_feature_count(q.kind);
  const auto stride = static_cast<std::size_t>(search::face_raw_columns(q.kind));
  features.resize(static_cast<Eigen::Index>(q.size()), nf);
  targets.resize(static_cast<Eigen::Index>(q.size()), 2);
  Eigen::Index kept = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    double f[20], base[2];
    int order[4];
    if (!search::face_canonical_form(q.kind, q.raw.data() + i * stride, f, order, base)) continue;
    double s = q.label[2 * i], t = q.label[2 * i + 1];
    search::face_param_to_canonical(q.kind, order, s, t);
    for (int k = 0; k < nf; ++k) features(kept, k) = f[k];
    // The network's target: the correction to the corner facet's closed form (face_network.hpp).
    targets(kept, 0) = s - base[0];
    targets(kept, 1) = t - base[1];
    ++kept;
  }
  features.conservativeResize(kept, nf);
  targets.conservativeResize(kept, 2);
}

FaceNetworkResult train_one(FaceKind kind, const std::vector<int>& hidden, const mlp::MatrixRM<double>& x,
                            const mlp::MatrixRM<double>& t, const FaceQueries& heldout,
                            const FaceStudyOptions& o, const FaceStudyLog& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const int nf = search::face_feature_count(kind);
  const Eigen::Index n = x.rows();
  const auto validation = static_cast<Eigen::Index>(o.validation_fraction * static_cast<double>(n));
  const Eigen::Index train = n - validation;
  // The corrections' range, symmetric about 0 and a little wider than the training set's.
  const double reach = 1.05 * std::max(t.topRows(train).cwiseAbs().maxCoeff(), 1e-6);
  mlp::Scaling scaling = mlp::Scaling::from_inputs(x.topRows(train), 2, -reach, reach, o.input_quantile);
  std::vector<int> sizes{nf};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(2);
  auto network = std::make_shared<mlp::Network<float>>(sizes, o.u0, scaling);
  network->initialize(o.seed);
  const auto scaled = [&](Eigen::Index first, Eigen::Index rows, mlp::MatrixRM<float>& sx,
                          mlp::MatrixRM<float>& st) {
    sx.resize(rows, nf);
    st.resize(rows, 2);
    for (Eigen::Index r = 0; r < rows; ++r) {
      for (int k = 0; k < nf; ++k) sx(r, k) = static_cast<float>(scaling.scale_input(k, x(first + r, k)));
      for (int k = 0; k < 2; ++k) st(r, k) = static_cast<float>(scaling.scale_target(k, t(first + r, k)));
    }
  };
  mlp::MatrixRM<float> tx, tt, vx, vt;
  scaled(0, train, tx, tt);
  scaled(train, validation, vx, vt);
  mlp::TrainOptions options;
  options.mode = mlp::TrainingMode::kOnline;
  options.learning_rate = o.learning_rate;
  options.learning_rate_final = o.learning_rate_final;
  options.momentum = o.momentum;
  options.epochs = o.epochs;
  options.seed = o.seed;
  options.threads = 1;
  mlp::Trainer<float> trainer(*network, options, tx, tt, vx, vt);
  const std::string name = size_name(nf, hidden);
  auto last = std::chrono::steady_clock::now();
  FaceNetworkResult r;
  r.epochs = trainer.train([&](const mlp::EpochReport& e) {
    if (log && std::chrono::duration<double>(std::chrono::steady_clock::now() - last).count() > 10.0) {
      last = std::chrono::steady_clock::now();
      std::ostringstream s;
      s << "  " << name << ": epoch " << e.epoch + 1 << " of " << o.epochs << ", validation loss "
        << e.validation_loss;
      log(s.str());
    }
    return true;
  });
  r.best_epoch = trainer.state().best_epoch;
  r.name = name;
  r.hidden = hidden;
  r.network = network;
  // The training domain: each feature between its extremes over the training rows.
  const Eigen::RowVectorXd lo = x.topRows(train).colwise().minCoeff(),
                           hi = x.topRows(train).colwise().maxCoeff();
  r.feature_min.assign(lo.data(), lo.data() + nf);
  r.feature_max.assign(hi.data(), hi.data() + nf);
  r.model = std::make_shared<search::FaceNetwork>(kind, *network, r.feature_min, r.feature_max);
  const search::FaceSearch alone(kind, search::Method::parse("network"), {}, r.model.get());
  std::vector<double> param;
  std::vector<Status> status;
  run_search(alone, heldout, param, status, o.threads);
  r.heldout_error = errors_of(param, status, heldout).mean;
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace

FaceNetworkResult train_face_network(FaceKind kind, const std::vector<int>& hidden, const FaceQueries& train,
                                     const FaceQueries& heldout, const FaceStudyOptions& options,
                                     const FaceStudyLog& log) {
  mlp::MatrixRM<double> x, t;
  canonical_set(train, x, t);
  return train_one(kind, hidden, x, t, heldout, options, log);
}

namespace {

void check_options(FaceKind kind, const FaceStudyOptions& options) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, kind != FaceKind::kTri3,
                       "tri3 faces need no study: their closed form (method closed_form) is exact");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, options.count >= 100 && options.heldout >= 100,
      "count and heldout must be at least 100, got " << options.count << " and " << options.heldout);
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, options.target > 0.0 && options.margin > 0.0,
      "target and margin must be positive, got " << options.target << " and " << options.margin);
  CONTACTNN_REQUIRE_AS(InvalidArgument, options.epochs >= 1 && !options.sizes.empty(),
                       "epochs must be at least 1 and sizes not empty");
}

void train_and_measure(FaceStudy& study, const FaceQueries& train, const FaceQueries& heldout,
                       const FaceStudyLog& log);

}  // namespace

FaceStudy run_face_study(const contact::Scene& scene, FaceKind kind, const FaceStudyOptions& options,
                         const FaceStudyLog& log) {
  const auto t0 = std::chrono::steady_clock::now();
  check_options(kind, options);
  const auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  FaceStudy study;
  study.kind = kind;
  study.options = options;
  // 1.
  study.pairs = face_pairs(scene, kind);
  CONTACTNN_REQUIRE_AS(InvalidArgument, study.pairs.faces > 0,
                       "the master surface has no " << search::to_string(kind) << " faces");
  CONTACTNN_REQUIRE_AS(InvalidArgument, study.pairs.pairs.size() > 0,
                       "no slave node's closest point lies inside a " << search::to_string(kind) << " face");
  study.capture = widened_capture(options.capture, study.pairs.largest_offset);
  {
    std::ostringstream s;
    s << "1. pairs: " << study.pairs.pairs.size() << " of " << study.pairs.slave_nodes
      << " slave nodes inside " << study.pairs.faces << " " << search::to_string(kind) << " faces; capture "
      << study.capture << " e";
    say(s.str());
  }
  // 2.
  const FaceQueries train =
      sample_face_domain(scene, kind, options, study.capture, options.count, options.seed);
  const FaceQueries heldout =
      sample_face_domain(scene, kind, options, study.capture, options.heldout, options.seed + 1000);
  study.train_count = train.size();
  study.heldout_count = heldout.size();
  say("2. domain: " + std::to_string(train.size()) + " training and " + std::to_string(heldout.size()) +
      " held-out configurations");
  train_and_measure(study, train, heldout, log);
  study.seconds = seconds_since(t0);
  return study;
}

FaceStudy run_general_face_study(FaceKind kind, const FaceStudyOptions& options, double curvature,
                                 const FaceStudyLog& log) {
  const auto t0 = std::chrono::steady_clock::now();
  check_options(kind, options);
  FaceStudy study;
  study.kind = kind;
  study.options = options;
  study.general_curvature = curvature;
  const FaceQueries train = sample_general_face_domain(kind, options, curvature, options.count, options.seed);
  const FaceQueries heldout =
      sample_general_face_domain(kind, options, curvature, options.heldout, options.seed + 1000);
  study.train_count = train.size();
  study.heldout_count = heldout.size();
  if (log)
    log("2. general domain: " + std::to_string(train.size()) + " training and " +
        std::to_string(heldout.size()) + " held-out configurations");
  train_and_measure(study, train, heldout, log);
  study.seconds = seconds_since(t0);
  return study;
}

namespace {

void train_and_measure(FaceStudy& study, const FaceQueries& train, const FaceQueries& heldout,
                       const FaceStudyLog& log) {
  const FaceKind kind = study.kind;
  const FaceStudyOptions& options = study.options;
  const auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  // 3.
  mlp::MatrixRM<double> x, t;
  canonical_set(train, x, t);
  for (const std::vector<int>& hidden : options.sizes) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, !hidden.empty() && hidden.size() <= 2,
                         "a size has one or two hidden layers, got " << hidden.size());
    say("3. training " + size_name(search::face_feature_count(kind), hidden));
    study.networks.push_back(train_one(kind, hidden, x, t, heldout, options, log));
    const FaceNetworkResult& r = study.networks.back();
    std::ostringstream s;
    s << "   " << r.name << ": held-out mean |error| " << r.heldout_error << " (" << r.seconds << " s)";
    say(s.str());
    if (r.heldout_error <= options.margin * options.target) break;
  }
  // 4.
  say("4. measuring the methods");
  struct Candidate {
    std::string name, method;
    int network;
  };
  std::vector<Candidate> candidates;
  for (const std::string& m : split_names(options.methods)) candidates.push_back({m, m, -1});
  for (std::size_t k = 0; k < study.networks.size(); ++k) {
    for (const std::string& m : split_names(options.network_methods)) {
      candidates.push_back({m + "[" + study.networks[k].name + "]", m, static_cast<int>(k)});
    }
  }
  std::vector<std::unique_ptr<search::FaceSearch>> searches;
  for (const Candidate& c : candidates) {
    const search::FaceNetwork* net =
        c.network >= 0 ? study.networks[static_cast<std::size_t>(c.network)].model.get() : nullptr;
    searches.push_back(std::make_unique<search::FaceSearch>(kind, search::Method::parse(c.method),
                                                            search::SearchOptions{}, net));
  }
  const double width = kind == FaceKind::kQuad8 ? 2.0 : 1.0;
  std::vector<double> param;
  std::vector<Status> status;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    FaceMethodResult r;
    r.name = candidates[k].name;
    r.method = candidates[k].method;
    r.network = candidates[k].network;
    run_search(*searches[k], heldout, param, status, options.threads);
    const Errors h = errors_of(param, status, heldout);
    r.heldout_mean = h.mean;
    r.heldout_max = h.max;
    r.heldout_failures = h.failures;
    r.heldout_effective =
        (h.mean * static_cast<double>(heldout.size() - static_cast<std::size_t>(h.failures)) +
         width * static_cast<double>(h.failures)) /
        static_cast<double>(heldout.size());
    const Errors p = study.pairs.pairs.size() > 0
                         ? (run_search(*searches[k], study.pairs.pairs, param, status, options.threads),
                            errors_of(param, status, study.pairs.pairs))
                         : Errors{};
    r.pairs_mean = p.mean;
    r.pairs_max = p.max;
    r.pairs_failures = p.failures;
    r.reaches = r.heldout_effective <= options.margin * options.target;
    study.methods.push_back(r);
  }
  // Time: round-robin passes over the first timing_queries held-out rows, batched, 1 thread; the fastest
  // pass.
  const std::size_t timed =
      std::min<std::size_t>(heldout.size(), static_cast<std::size_t>(options.timing_queries));
  std::vector<double> best(candidates.size(), std::numeric_limits<double>::infinity());
  std::vector<double> tp(2 * timed);
  std::vector<Status> ts(timed);
  for (int pass = 0; pass < options.timing_passes; ++pass) {
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const auto start = std::chrono::steady_clock::now();
      searches[k]->run<double>(timed, heldout.raw.data(),
                               search::Results<double>{tp.data(), nullptr, ts.data()}, 1);
      best[k] = std::min(best[k], seconds_since(start) * 1e9 / static_cast<double>(timed));
    }
  }
  for (std::size_t k = 0; k < candidates.size(); ++k) study.methods[k].batched_ns = best[k];
  for (std::size_t k = 0; k < study.methods.size(); ++k) {
    const FaceMethodResult& m = study.methods[k];
    if (!m.reaches) continue;
    if (study.chosen < 0 || m.batched_ns < study.methods[static_cast<std::size_t>(study.chosen)].batched_ns) {
      study.chosen = static_cast<int>(k);
    }
  }
}

}  // namespace

std::string face_study_markdown(const FaceStudy& st, const std::string& deck, int pair) {
  std::ostringstream o;
  const std::string kind(search::to_string(st.kind));
  const std::string units =
      st.kind == FaceKind::kQuad8 ? "(xi, eta) units, domain width 2" : "(r, s) units, domain width 1";
  const bool general = st.general_curvature >= 0.0;
  if (general) {
    o << "# General face network: " << kind << " faces of the paper-like domain\n\n";
    o << "- Domain (lib/study/face_study.hpp, sample_general_face_domain): A = (0, 0, 0), B = (1, 0, 0), the "
         "last corner "
         "at 0.5 to 1 from A and 60 to 120 degrees from AB"
      << (st.kind == FaceKind::kQuad8 ? ", C at B + D moved by up to 0.3 in each coordinate" : "")
      << ", mid-side nodes up to " << st.general_curvature
      << " x their edge off its midpoint in each coordinate, S within 0.3 of the face over a foot in it; "
      << st.train_count << " training and " << st.heldout_count << " held-out configurations (seeds "
      << st.options.seed << ", " << st.options.seed + 1000 << "). No deck: no pairs.\n";
  } else {
    o << "# Face study: " << deck << ", pair " << pair << ", " << kind << " faces\n\n";
    o << "- Pairs: " << st.pairs.pairs.size() << " of " << st.pairs.slave_nodes
      << " slave nodes lie inside one of the " << st.pairs.faces << " " << kind << " master faces ("
      << st.pairs.on_kind
      << " on such a face in all, the others on its edges or vertices: no local search needed).\n";
    o << "- Domain: the scene's " << kind << " faces, nodes moved by up to " << st.options.deformation
      << " e, S within " << std::setprecision(3) << st.capture
      << " e of the face (e: the face's shortest corner edge); " << st.train_count << " training and "
      << st.heldout_count << " held-out configurations (seeds " << st.options.seed << ", "
      << st.options.seed + 1000 << ").\n";
  }
  o << "- Target: mean |error| " << st.options.target << " in " << units << "; a method reaches it at "
    << st.options.margin
    << " x target on the held-out sample (effective mean: a failure counts as one domain width).\n";
  o << "- Whole study: " << std::setprecision(3) << st.seconds << " s.\n\n";
  o << "## Scene networks\n\n| network | epochs (best) | held-out mean \\|error\\| | training s "
       "|\n|---|---|---|---|\n";
  for (const FaceNetworkResult& n : st.networks) {
    o << "| " << n.name << " | " << n.epochs << " (" << n.best_epoch << ") | " << std::setprecision(3)
      << n.heldout_error << " | " << std::setprecision(3) << n.seconds << " |\n";
  }
  o << "\n## Every method\n\nHeld-out: the " << (general ? "general" : "scene's")
    << " domain, never trained on."
    << (general ? "" : " Pairs: the deck's own, labelled by the surface search.")
    << " ns: batched, 1 thread, the fastest of " << st.options.timing_passes << " passes.\n\n";
  o << "| method | held-out mean | effective | max | failures |"
    << (general ? "" : " pairs mean | pairs max | pairs failures |") << " ns/query | reaches |\n";
  o << "|---|---|---|---|---|" << (general ? "" : "---|---|---|") << "---|---|\n";
  for (std::size_t k = 0; k < st.methods.size(); ++k) {
    const FaceMethodResult& m = st.methods[k];
    o << "| " << (static_cast<int>(k) == st.chosen ? "**" + m.name + "**" : m.name) << " | "
      << std::setprecision(3) << m.heldout_mean << " | " << m.heldout_effective << " | " << m.heldout_max
      << " | " << m.heldout_failures << " | ";
    if (!general) o << m.pairs_mean << " | " << m.pairs_max << " | " << m.pairs_failures << " | ";
    o << std::setprecision(3) << m.batched_ns << " | " << (m.reaches ? "yes" : "no") << " |\n";
  }
  o << "\n## The choice\n\n";
  if (st.chosen >= 0) {
    const FaceMethodResult& c = st.methods[static_cast<std::size_t>(st.chosen)];
    o << "**" << c.name << "**: the fastest method that reaches the target on the held-out sample ("
      << std::setprecision(3) << c.batched_ns << " ns per query; held-out " << c.heldout_effective;
    if (!general) o << ", the deck's pairs " << c.pairs_mean;
    o << ").\n";
  } else {
    o << "No method reaches the target on the held-out sample.\n";
  }
  o << "\n## The fastest method at each accuracy level (held-out effective mean)\n\n| level | method | "
       "ns/query |\n|---|---|---|\n";
  for (const double level : {1e-1, 1e-2, 5e-3, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10}) {
    int best = -1;
    for (std::size_t k = 0; k < st.methods.size(); ++k) {
      if (st.methods[k].heldout_effective > level) continue;
      if (best < 0 || st.methods[k].batched_ns < st.methods[static_cast<std::size_t>(best)].batched_ns)
        best = static_cast<int>(k);
    }
    o << "| " << level << " | " << (best >= 0 ? st.methods[static_cast<std::size_t>(best)].name : "none")
      << " | ";
    if (best >= 0) o << std::setprecision(3) << st.methods[static_cast<std::size_t>(best)].batched_ns;
    o << " |\n";
  }
  return o.str();
}

}  // namespace contactnn::study
