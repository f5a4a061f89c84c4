#include "study/node_orders.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dataset/labeller.hpp"

namespace contactnn::study {

namespace {

/// Where node i of the identity order goes in the order (rotation, mirror) (scripts/node-orders' convention).
int caller_node(int rotation, bool mirror, int i) { return ((mirror ? (4 - i) % 4 : i) + rotation) % 4; }

/// The identity order's local coordinates as the order (rotation, mirror) reports them (SPEC 4).
std::array<double, 2> to_caller(int rotation, bool mirror, std::array<double, 2> p, double centre) {
  double x = p[0] - centre, y = p[1] - centre;
  if (mirror) std::swap(x, y);
  for (int r = 0; r < rotation; ++r) {
    const double t = x;
    x = -y;
    y = t;
  }
  return {x + centre, y + centre};
}

bool has_point(Status s) { return s == Status::kOk || s == Status::kOutside || s == Status::kOutOfDomain; }

}  // namespace

std::string NodeOrderCheck::summary() const {
  char line[300];
  if (scene_network >= 0.0) {
    std::snprintf(
        line, sizeof line,
        "node orders: %ld pairs x 8 orders; largest difference: labels %.3g (gap %.3g), plan's method %.3g, "
        "scene network %.3g: %s",
        pairs, label, label_gap, plan_method, scene_network, passed ? "passed" : "FAILED");
  } else {
    std::snprintf(line, sizeof line,
                  "node orders: %ld pairs x 8 orders; largest difference: labels %.3g (gap %.3g), plan's "
                  "method %.3g: %s",
                  pairs, label, label_gap, plan_method, passed ? "passed" : "FAILED");
  }
  return line;
}

NodeOrderCheck check_node_orders(const ScenePairs& pairs, SurfaceKind surface,
                                 const search::LocalSearch& plan, const search::LocalSearch* scene) {
  constexpr double kLabelTolerance = 1e-12;  // SPEC 4: the same canonical configuration in every order
  constexpr double kMethodTolerance =
      1e-6;  // float networks: the same canonical input, rounding of the map back
  NodeOrderCheck check;
  const eval::EvaluationSet& set = pairs.quad4_pairs;
  const auto n = static_cast<std::size_t>(set.rows());
  check.pairs = static_cast<long>(n);
  if (scene != nullptr) check.scene_network = 0.0;
  if (n == 0) return check;
  const auto cols = static_cast<std::size_t>(eval::EvaluationSet::raw_columns(surface));
  const double centre = surface == SurfaceKind::kGregory ? 0.5 : 0.0;
  const bool gregory = surface == SurfaceKind::kGregory;
  struct Answers {
    std::vector<dataset::Label> labels;
    std::vector<double> plan_param, scene_param;
    std::vector<Status> plan_status, scene_status;
  };
  const auto answers_in = [&](int rotation, bool mirror) {
    Answers a;
    std::vector<double> raw(n * cols);
    for (std::size_t r = 0; r < n; ++r) {
      const double* in = set.raw.data() + r * cols;
      double* out = raw.data() + r * cols;
      for (int i = 0; i < 4; ++i) {
        const int k = caller_node(rotation, mirror, i);
        for (int x = 0; x < 3; ++x) {
          out[3 * k + x] = in[3 * i + x];
          if (gregory) out[15 + 3 * k + x] = in[15 + 3 * i + x];
        }
      }
      for (int x = 12; x < 15; ++x) out[x] = in[x];
      geometry::Configuration c{};
      for (int i = 0; i < 4; ++i) {
        c.nodes[static_cast<std::size_t>(i)] = geometry::Vec3(out[3 * i], out[3 * i + 1], out[3 * i + 2]);
        if (gregory)
          c.normals[static_cast<std::size_t>(i)] =
              geometry::Vec3(out[15 + 3 * i], out[16 + 3 * i], out[17 + 3 * i]);
      }
      c.slave = geometry::Vec3(out[12], out[13], out[14]);
      a.labels.push_back(dataset::label_configuration(c, surface));
    }
    const auto run = [&](const search::LocalSearch& s, std::vector<double>& param,
                         std::vector<Status>& status) {
      param.assign(2 * n, 0.0);
      status.assign(n, Status::kInvalid);
      s.run(n, raw.data(), search::Results<double>{param.data(), nullptr, status.data(), nullptr});
    };
    run(plan, a.plan_param, a.plan_status);
    if (scene != nullptr) run(*scene, a.scene_param, a.scene_status);
    return a;
  };
  const Answers identity = answers_in(0, false);
  for (const bool mirror : {false, true}) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      const Answers a = rotation == 0 && !mirror ? identity : answers_in(rotation, mirror);
      const double sign = mirror ? -1.0 : 1.0;
      for (std::size_t r = 0; r < n; ++r) {
        const dataset::Label &base = identity.labels[r], &l = a.labels[r];
        if (base.status != l.status) {
          check.passed = false;
          continue;
        }
        if (base.status == Status::kOk || base.status == Status::kOutside) {
          const auto want = to_caller(rotation, mirror, base.param, centre);
          check.label =
              std::max({check.label, std::abs(l.param[0] - want[0]), std::abs(l.param[1] - want[1])});
          check.label_gap = std::max(check.label_gap, std::abs(l.gap - sign * base.gap));
        }
        const auto compare = [&](const std::vector<double>& p0, const std::vector<Status>& s0,
                                 const std::vector<double>& p, const std::vector<Status>& s, double& worst) {
          if (s0[r] != s[r]) {
            check.passed = false;
            return;
          }
          if (!has_point(s0[r])) return;
          const auto want = to_caller(rotation, mirror, {p0[2 * r], p0[2 * r + 1]}, centre);
          worst = std::max({worst, std::abs(p[2 * r] - want[0]), std::abs(p[2 * r + 1] - want[1])});
        };
        compare(identity.plan_param, identity.plan_status, a.plan_param, a.plan_status, check.plan_method);
        if (scene != nullptr) {
          compare(identity.scene_param, identity.scene_status, a.scene_param, a.scene_status,
                  check.scene_network);
        }
      }
    }
  }
  check.passed = check.passed && check.label <= kLabelTolerance && check.plan_method <= kMethodTolerance &&
                 check.scene_network <= kMethodTolerance;
  return check;
}

}  // namespace contactnn::study
