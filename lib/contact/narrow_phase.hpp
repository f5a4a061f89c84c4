// The surface search's narrow phase with a method of the user's choice (issue 38: the plan in the loop): a
// face locator that answers a candidate (slave point, face) pair by one of lib/search's methods (LocalSearch
// on quad4 faces, FaceSearch on tri6 and quad8), or refuses it so that the exact closest point is taken.
//
// SearchOptions::interior points at one (null: the exact search alone). For each candidate face the surface
// search asks it first (surface_search.hpp, step 2):
//  - the method runs on the pair in the face's own node order (quad4: the surface the search gives the face,
//    bilinear facet or Gregory patch; a network method only on quad4 faces of its network's surface);
//  - its answer is taken when its status is ok and its local coordinates lie inside the closed face domain
//    ([-1, 1]^2 bilinear and quad8, [0, 1]^2 Gregory, r, s >= 0 and r + s <= 1 on a tri6): the point P
//    of the face's surface there, location face, distance |S - P|, the unit normal P_s x P_t, the method's
//    Newton steps as its iterations;
//  - otherwise (any other status, a point outside the face, a face the method does not apply to: tri3, whose
//    closest point is exact already, or a face type the method has no network for) it refuses, and the
//    search takes the face's exact closest point (interior, edge or vertex) as without a locator; the search
//    also takes the exact point where the method's lies beyond the capture distance.
// So a slave point the exact search answers is never left without a point: the exact answer's face F has a
// bound at most its distance d, every point a face gives (the method's too: a point of the surface) is at
// least d away, so the scan reaches F, whose point is then within the capture distance. Only face interior
// points carry the method's error. The search reports which answered (NodeSegmentPair::by_method).
//
// The method's own convergence tests decide "ok": newton:K after K steps, newton until the step is below
// tol_param, the hybrids after their safeguarded steps (search/local_search.hpp). start+newton:K needs a
// start the search does not have: refused at construction.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"
#include "mesh/surface_mesh.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::search {
class NetworkModel;
struct Method;
}  // namespace contactnn::search

namespace contactnn::contact {

using geometry::Vec3;

class FaceLocator {
 public:
  /// `method`: a search::Method name (InvalidArgument for one that does not parse, start+newton:K, or a
  /// network method without `network`). `network` must outlive the locator; its surface kind is the only
  /// quad4 surface a network method applies to.
  explicit FaceLocator(const std::string& method, const search::NetworkModel* network = nullptr);
  ~FaceLocator();
  FaceLocator(FaceLocator&&) noexcept;
  FaceLocator& operator=(FaceLocator&&) noexcept;

  /// The method's point of face f of `master` for `slave` (header), or nothing: the exact answer is wanted.
  /// `kind` is the surface the search gives a quad4 face (ignored for the other types); `normals` the
  /// master's unit node normals (Gregory). Thread-safe.
  [[nodiscard]] std::optional<projection::FaceClosestPoint> locate(const mesh::SurfaceMesh& master,
                                                                   std::span<const Vec3> normals,
                                                                   SurfaceKind kind, int f,
                                                                   const Vec3& slave) const;

  [[nodiscard]] const search::Method& method() const;
  [[nodiscard]] std::string name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace contactnn::contact
