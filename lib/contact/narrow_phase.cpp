#include "contact/narrow_phase.hpp"

#include <array>
#include <cmath>

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "search/face_search.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"

namespace contactnn::contact {

namespace {

/// Inside the closed domain of a quadrilateral face: [lo, hi]^2.
bool inside_quad(const std::array<double, 2>& p, ParamDomain d) {
  return p[0] >= d.lo && p[0] <= d.hi && p[1] >= d.lo && p[1] <= d.hi;
}

/// Inside the closed triangle r, s >= 0, r + s <= 1.
bool inside_triangle(const std::array<double, 2>& p) {
  return p[0] >= 0.0 && p[1] >= 0.0 && p[0] + p[1] <= 1.0;
}

/// The answer at local coordinates `param` of `surface`: its point, distance, unit normal; location face.
template <class SurfaceT>
projection::FaceClosestPoint answer_at(const SurfaceT& surface, const std::array<double, 2>& param,
                                       const Vec3& slave, int iterations) {
  const geometry::SurfacePoint sp = surface.evaluate(param[0], param[1]);
  projection::FaceClosestPoint p;
  p.param = param;
  p.point = sp.position;
  const Vec3 n = sp.d_s.cross(sp.d_t);
  const double length = n.norm();
  p.normal = length > 0.0 && std::isfinite(length) ? Vec3(n / length) : Vec3(Vec3::Zero());
  p.distance = (slave - sp.position).norm();
  p.location = Location::kFace;
  p.iterations = iterations;
  p.by_method = true;
  p.status = std::isfinite(p.distance) ? Status::kOk : Status::kInvalid;
  return p;
}

}  // namespace

struct FaceLocator::Impl {
  search::Method method;
  std::optional<search::LocalSearch> bilinear, gregory;  ///< quad4 faces on each surface
  std::optional<search::FaceSearch> tri6, quad8;

  /// One query through `search` (15 or 27 values, or a face's raw row): param, status and iterations.
  template <class Search>
  static Status run(const Search& search, const double* raw, std::array<double, 2>& param,
                    std::int32_t& iterations) {
    double gap = 0.0;
    Status status = Status::kInvalid;
    search.template run<double>(1, raw, {param.data(), &gap, &status, &iterations, nullptr}, 1);
    return status;
  }

  std::optional<projection::FaceClosestPoint> quad4(const mesh::SurfaceMesh& master,
                                                    std::span<const Vec3> normals, SurfaceKind kind, int f,
                                                    const Vec3& slave) const {
    const std::optional<search::LocalSearch>& search = kind == SurfaceKind::kGregory ? gregory : bilinear;
    if (!search) return std::nullopt;
    std::array<double, 27> raw{};
    std::array<Vec3, 4> x, n;
    const std::span<const int> corners = master.face_corners(f);
    for (std::size_t i = 0; i < 4; ++i) {
      const auto node = static_cast<std::size_t>(corners[i]);
      x[i] = master.positions[node];
      n[i] = kind == SurfaceKind::kGregory ? normals[node] : Vec3::Zero();
      for (std::size_t k = 0; k < 3; ++k) {
        raw[3 * i + k] = x[i][static_cast<Eigen::Index>(k)];
        raw[15 + 3 * i + k] = n[i][static_cast<Eigen::Index>(k)];
      }
    }
    for (std::size_t k = 0; k < 3; ++k) raw[12 + k] = slave[static_cast<Eigen::Index>(k)];
    std::array<double, 2> param{};
    std::int32_t iterations = 0;
    if (run(*search, raw.data(), param, iterations) != Status::kOk || !inside_quad(param, param_domain(kind)))
      return std::nullopt;
    if (kind == SurfaceKind::kGregory)
      return answer_at(geometry::GregoryPatch(x, n), param, slave, iterations);
    return answer_at(geometry::BilinearPatch(x), param, slave, iterations);
  }

  template <std::size_t N, class Face>
  std::optional<projection::FaceClosestPoint> quadratic(const search::FaceSearch& search,
                                                        const mesh::SurfaceMesh& master,
                                                        const mesh::FaceNodes& nodes,
                                                        const Vec3& slave) const {
    std::array<double, 3 * N + 3> raw{};
    std::array<Vec3, N> x;
    for (std::size_t i = 0; i < N; ++i) {
      x[i] = master.positions[static_cast<std::size_t>(nodes.nodes[i])];
      for (std::size_t k = 0; k < 3; ++k) raw[3 * i + k] = x[i][static_cast<Eigen::Index>(k)];
    }
    for (std::size_t k = 0; k < 3; ++k) raw[3 * N + k] = slave[static_cast<Eigen::Index>(k)];
    std::array<double, 2> param{};
    std::int32_t iterations = 0;
    if (run(search, raw.data(), param, iterations) != Status::kOk) return std::nullopt;
    const bool inside =
        N == 6 ? inside_triangle(param) : inside_quad(param, param_domain(SurfaceKind::kBilinear));
    if (!inside) return std::nullopt;
    return answer_at(Face(x), param, slave, iterations);
  }
};

FaceLocator::FaceLocator(const std::string& name, const search::NetworkModel* network)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.method = search::Method::parse(name);
  CONTACTNN_REQUIRE_AS(InvalidArgument, !m.method.needs_start(),
                       "method '" << name << "': the surface search has no start to give it");
  CONTACTNN_REQUIRE_AS(InvalidArgument, !m.method.needs_network() || network != nullptr,
                       "method '" << name << "' needs a network");
  // Each face type the method applies to (the header): a network method on its network's quad4 surface only,
  // four_triangles on bilinear quad4 faces only.
  const bool four = m.method.start == search::Method::Start::kFourTriangles;
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    if (m.method.needs_network() && network->surface() != kind) continue;
    if (four && kind == SurfaceKind::kGregory) continue;
    auto& slot = kind == SurfaceKind::kBilinear ? m.bilinear : m.gregory;
    slot.emplace(kind, m.method, search::SearchOptions{}, m.method.needs_network() ? network : nullptr);
  }
  if (!m.method.needs_network() && !four) {
    m.tri6.emplace(search::FaceKind::kTri6, m.method);
    m.quad8.emplace(search::FaceKind::kQuad8, m.method);
  }
}

FaceLocator::~FaceLocator() = default;
FaceLocator::FaceLocator(FaceLocator&&) noexcept = default;
FaceLocator& FaceLocator::operator=(FaceLocator&&) noexcept = default;

std::optional<projection::FaceClosestPoint> FaceLocator::locate(const mesh::SurfaceMesh& master,
                                                                std::span<const Vec3> normals,
                                                                SurfaceKind kind, int f,
                                                                const Vec3& slave) const {
  const mesh::FaceNodes nodes = master.face_nodes(f);
  switch (nodes.type) {
    case mesh::FaceType::kQuad4: return impl_->quad4(master, normals, kind, f, slave);
    case mesh::FaceType::kTri6:
      if (!impl_->tri6) return std::nullopt;
      return impl_->quadratic<6, geometry::QuadraticTriangle>(*impl_->tri6, master, nodes, slave);
    case mesh::FaceType::kQuad8:
      if (!impl_->quad8) return std::nullopt;
      return impl_->quadratic<8, geometry::SerendipityQuad>(*impl_->quad8, master, nodes, slave);
    default: return std::nullopt;  // tri3: the exact closest point costs less than any method
  }
}

const search::Method& FaceLocator::method() const { return impl_->method; }

std::string FaceLocator::name() const { return impl_->method.name(); }

}  // namespace contactnn::contact
