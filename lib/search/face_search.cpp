#include "search/face_search.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "projection/closest_point_on_face.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"
#include "search/face_block.hpp"
#include "search/face_network.hpp"
#include "search/search_run.hpp"

namespace contactnn::search {

namespace {
constexpr std::array<std::string_view, 3> kFaceKindNames = {"tri3", "tri6", "quad8"};
}  // namespace

std::string_view to_string(FaceKind kind) { return enum_name(kFaceKindNames, kind, "?"); }

FaceKind face_kind_from_string(std::string_view name) {
  if (const auto kind = enum_from_name<FaceKind>(kFaceKindNames, name)) return *kind;
  CONTACTNN_REQUIRE_AS(InvalidArgument, false,
                       "unknown face type '" << quote_text(name) << "', expected tri3, tri6 or quad8");
  return FaceKind::kTri3;
}

FaceSearch::FaceSearch(FaceKind kind, Method method, SearchOptions options, const FaceNetwork* network) {
  detail::check_method_steps(method);
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, method.start != Method::Start::kFourTriangles,
      "method four_triangles splits a 4-node quad; it has no form for " << to_string(kind) << " faces");
  CONTACTNN_REQUIRE_AS(InvalidArgument, !method.to_convergence || method.start == Method::Start::kCentre,
                       "Newton to convergence starts from the centre; got start " << method.name());
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, !method.needs_network() || kind != FaceKind::kTri3,
      "method " << method.name()
                << " on tri3 faces: a flat triangle's closed form is exact (method closed_form), "
                   "no network is made for it");
  detail::check_network(
      method, network, kind, [](const FaceNetwork& n) { return n.face(); }, "faces");
  auto plan = detail::new_plan<detail::FacePlan>(kind, method, options, network);
  // Widths: 1 for a triangle's (r, s), 2 for the quad's (xi, eta). The hybrids' box is the quads'
  // (SearchOptions:: bilinear_box_margin widths beyond the face): a face's closest point beyond that is no
  // contact on it.
  const double width = kind == FaceKind::kQuad8 ? 2.0 : 1.0;
  plan->box_margin = options.bilinear_box_margin * width;
  plan->max_step = options.max_step_widths * width;
  const detail::IsaKernels& kernels = detail::isa_kernels(kernel_isa());
  plan->isa = kernels.isa;
  kernels.select_face(*plan);
  plan_ = std::move(plan);
}

FaceKind FaceSearch::face() const { return plan_->kind; }
const Method& FaceSearch::method() const { return plan_->method; }
const SearchOptions& FaceSearch::options() const { return plan_->options; }
int FaceSearch::block_size() const { return plan_->block_size; }

namespace {

/// An answer outside the face moved to the nearest point of its boundary
/// (SearchOptions::closest_point_on_face): the straight edges of tri3
/// (projection::closest_point_on_triangle), the quadratic curves of tri6 and quad8
/// (projection::closest_point_on_quadratic_edge), ends included. Gap +-|S - P| by the face normal at P.
using geometry::Vec3;

template <class Real>
void move_to_boundary(FaceKind kind, const Real* raw, Real* param, Real* gap, Status* status,
                      Location* location) {
  const int nodes = face_node_count(kind);
  // Relative to the face's first node: the projection then rounds at the face's size, not at its distance
  // from the origin (issue 39: 2e6 face sizes away, the boundary point was 1e-5 off in the parameters).
  const double origin[3] = {static_cast<double>(raw[0]), static_cast<double>(raw[1]),
                            static_cast<double>(raw[2])};
  const auto vec = [raw, &origin](int i) {
    return Vec3(static_cast<double>(raw[3 * i]) - origin[0], static_cast<double>(raw[3 * i + 1]) - origin[1],
                static_cast<double>(raw[3 * i + 2]) - origin[2]);
  };
  const Vec3 s = vec(nodes);
  std::array<double, 2> p{};
  Vec3 point, normal;
  Location where = Location::kEdge;
  if (kind == FaceKind::kTri3) {
    // The whole triangle's closest point: outside its interior it is on the boundary.
    const projection::FaceClosestPoint c = projection::closest_point_on_triangle({vec(0), vec(1), vec(2)}, s);
    if (c.status != Status::kOk) return;
    p = c.param;
    point = c.point;
    normal = c.normal;
    where = c.location;
  } else {
    const auto nearest = [&](const auto& face, int edges) {
      projection::EdgePoint best;
      best.distance = std::numeric_limits<double>::infinity();
      for (int e = 0; e < edges; ++e) {
        const projection::EdgePoint q = projection::closest_point_on_quadratic_edge(face, e, s);
        if (q.distance < best.distance) best = q;
      }
      const geometry::SurfacePoint at = face.evaluate(best.param[0], best.param[1]);
      p = best.param;
      point = at.position;
      normal = at.d_s.cross(at.d_t);
    };
    if (kind == FaceKind::kTri6) {
      std::array<Vec3, 6> x;
      for (int i = 0; i < 6; ++i) x[static_cast<std::size_t>(i)] = vec(i);
      nearest(geometry::QuadraticTriangle(x), 3);
    } else {
      std::array<Vec3, 8> x;
      for (int i = 0; i < 8; ++i) x[static_cast<std::size_t>(i)] = vec(i);
      nearest(geometry::SerendipityQuad(x), 4);
    }
  }
  const Vec3 d = s - point;
  const double distance = d.norm();
  if (!std::isfinite(distance) || !std::isfinite(p[0]) || !std::isfinite(p[1])) return;
  param[0] = static_cast<Real>(p[0]);
  param[1] = static_cast<Real>(p[1]);
  *status = Status::kOk;
  if (gap != nullptr) *gap = static_cast<Real>(d.dot(normal) < 0.0 ? -distance : distance);
  if (location != nullptr && kind == FaceKind::kTri3) {
    *location = where;
  } else if (location != nullptr) {
    constexpr double kTol = projection::kOnBoundaryTolerance;
    int bounds = 0;
    if (kind == FaceKind::kQuad8) {
      bounds =
          (std::fabs(std::fabs(p[0]) - 1.0) <= 2.0 * kTol) + (std::fabs(std::fabs(p[1]) - 1.0) <= 2.0 * kTol);
    } else {
      bounds = (std::fabs(p[0]) <= kTol) + (std::fabs(p[1]) <= kTol) + (std::fabs(1.0 - p[0] - p[1]) <= kTol);
    }
    *location = bounds >= 2 ? Location::kVertex : (bounds == 1 ? Location::kEdge : Location::kFace);
  }
}

}  // namespace

template <class Real>
void FaceSearch::run(std::size_t count, const Real* raw, const Results<Real>& out, int threads) const {
  if (!detail::queries_to_run(count, raw, out, "FaceSearch::run")) return;
  const detail::FacePlan& plan = *plan_;
  const auto kernels = detail::block_kernels<Real>(plan);
  const auto block = kernels.block, single = kernels.single;
  const detail::BlockSplit split(count, plan.block_size, plan.options.min_parallel_count, threads);
  split.each_block([&](std::size_t first) { block(plan, raw, out, first); });
  split.each_rest(count, [&](std::size_t i) { single(plan, raw, out, i); });

  if (out.location != nullptr) std::fill(out.location, out.location + count, Location::kFace);
  if (plan.options.closest_point_on_face) {
    const auto columns = static_cast<std::size_t>(face_raw_columns(plan.kind));
    for (std::size_t i = 0; i < count; ++i) {
      if (out.status[i] != Status::kOutside) [[likely]]
        continue;
      move_to_boundary(plan.kind, raw + i * columns, out.param + 2 * i,
                       out.gap != nullptr ? out.gap + i : nullptr, out.status + i,
                       out.location != nullptr ? out.location + i : nullptr);
    }
  }
}

template void FaceSearch::run<float>(std::size_t, const float*, const Results<float>&, int) const;
template void FaceSearch::run<double>(std::size_t, const double*, const Results<double>&, int) const;

}  // namespace contactnn::search
