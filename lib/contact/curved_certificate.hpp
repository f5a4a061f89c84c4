// The closest point of a curved face (quad8, tri6, or a quad4's Gregory patch) to a slave node in one Newton
// run, certified to be the face's closest point, with the reference (lib/projection's sampled starts) only
// where no certificate holds: the curved faces' BilinearCertificate (bilinear_certificate.hpp, the model).
//
// For the face P(s, t) and f = |S - P|^2 / 2, with r = S - P and J = [P_s P_t],
//   grad f = -(P_s.r, P_t.r),   Hess f = J^T J - M,   M = [[r.P_ss, r.P_st], [r.P_st, r.P_tt]],
// and for any direction w, w^T Hess f w >= (lambda_min(J^T J) - lambda_max(M)) |w|^2 (Weyl), lambda_max(M) <=
// max(m00, m11) + |m01| (Gershgorin). Both terms are bounded over the whole face by numbers computed once per
// face and state.
//
// quad8 and tri6 (polynomial faces):
//  - r.v for a second derivative v: the face is P = sum_ij B_ij Q_ij over its Bezier control points Q_ij
//    (Bernstein B_ij >= 0, summing to 1), so r = sum_ij B_ij (S - Q_ij); v is constant (tri6) or affine in
//    each parameter (quad8: P_ss in t, P_tt in s, P_st in both), a mix with weights >= 0 of its values v_k at
//    the face's corners (its extreme parameters). Hence r.v <= max_k (S.v_k - lo_k) and |r.v| <=
//    max_k max(|S.v_k - lo_k|, |S.v_k - hi_k|), [lo_k, hi_k] the range of Q_ij.v_k over the control points
//    (once per face): a few dot products per slave. m00 and m11 are bounded signed (on the convex side of a
//    curved face they are negative: the curvature helps), m01 in magnitude;
//  - lambda_min(J^T J) = (tr - sqrt(tr^2 - 4 det)) / 2 grows with det = |P_s x P_t|^2 and falls with
//    tr = |P_s|^2 + |P_t|^2. |P_s x P_t| >= (P_s x P_t).n (n the unit normal at the face's centre), a
//    polynomial bounded below by its Bernstein coefficients (the products of the derivatives' Bezier forms,
//    degree (3, 3) for a quad8, 2 for a tri6); |P_s|^2 <= the largest |D|^2 over the Bezier coefficients D of
//    P_s (a convex function of a convex combination), and the same for P_t.
//
// The Gregory patch (geometry/gregory_patch.hpp, (u, v) in [0, 1]^2) is rational: P = sum B_i B_j b_ij +
// sum_k g_k delta_k, the bicubic on its 16 points b_ij (the interior ones P_ij1) plus, for each interior
// point, g_k = B_i(u) B_j(v) w_k(u, v) times delta_k = P_ij0 - P_ij1. The four g_k are reflections of one
// fixed function, whose second derivatives are bounded on the closed square (of degree 0 near the corner
// where w's denominator vanishes): sum_k |g_k,uu| <= 18, sum_k |g_k,uv| <= 9, sum_k |g_k,vv| <= 19.5
// (kGregoryBound, checked by a test on a dense grid and on circles about the corners). So over the square
//  - |P_ss| <= U_ss = max |6 D_ss b| (the bicubic's second differences, its Bezier form) + 18 max |delta_k|,
//    and likewise U_tt and U_st (9 D_s D_t b, 9 max |delta_k|); each bound is kept in two parts, along the
//    unit normal n at the centre and across it (GregoryBounds::second);
//  - r = S - P with P in the hull of the 20 control points: |r.n| is at most S's height beyond their range
//    along n, |r across n| at most its distance across n from their mean plus theirs, and
//    |r.v| <= |r.n| |v.n| + |r across| |v across| for each second derivative v. Near its tangent plane a
//    patch's second derivatives are mostly normal and r mostly across: the split is what lets a curved face
//    be certified for the slaves near it;
//  - lambda_max(M) <= max(|m00|, |m11|) + |m01| with those bounds;
//  - sigma_min(J) >= sigma_min(J at a point) - |J - J(point)|_F, the change bounded by the second derivatives
//    over half the width of the square about the point: the centre for the whole square, or (where that is
//    loose) the centres of its 2 x 2 sub-squares; lambda_min(J^T J) >= that squared.
//
// Where the bound of lambda_max(M) < kMargin x lambda_floor, f is strictly convex on the face (a convex
// domain): its minimum over the closed face is unique, an interior stationary point is that minimum, and a
// boundary point that meets the Karush-Kuhn-Tucker conditions is that minimum. One Newton run (from the
// centre, or from a tracked node's previous point) and the curved edges then give the reference's answer; a
// run that does not end on a certified point returns nothing, and the caller takes the reference.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <variant>

#include "contact/face_slots.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact {

using geometry::Vec3;

/// Bounds over [0, 1]^2 of sum_k |g_k,uu|, sum_k |g_k,uv|, sum_k |g_k,vv| for the four reflections g_k of
/// g(u, v) = B_1(u) B_1(v) u / (u + v), B_1(x) = 3 x (1 - x)^2 (the header: g(u, v), g(1 - u, v), g(u, 1 -
/// v), g(1 - u, 1 - v)): the suprema are 18, 9 (each in the limit at a corner) and 19.5; these hold 1% more.
inline constexpr std::array<double, 3> kGregoryBound = {18.18, 9.09, 19.7};

/// A quad8, tri6 or Gregory face prepared once per state of the master: its nodes relative to its first node
/// (as the reference projection moves it) and the certificate's bounds.
struct CurvedCertificate {
  bool triangle = false;       ///< a tri6 (nodes 0..5) rather than a quad8 (nodes 0..7) or a Gregory patch
  Vec3 origin = Vec3::Zero();  ///< the face's first node; everything below is relative to it
  /// The face on its nodes minus origin (as the reference moves it), built once.
  /// A Gregory patch (1.2 KB) is held where prepare_gregory was told to build it (CurvedCertificates' side
  /// table), so that a quad8 or tri6 certificate does not carry its room (the certificates of a fresh state
  /// are pages written anew).
  std::variant<std::monostate, geometry::SerendipityQuad, geometry::QuadraticTriangle,
               const geometry::GregoryPatch*>
      face;
  /// Each edge's sphere about the mean of its Bezier control points (the edge lies in their hull): the edges
  /// it shows farther than a nearer point are not searched.
  std::array<Vec3, 4> edge_centre{};
  std::array<double, 4> edge_radius{};
  /// Each edge's largest distance from its chord, the segment from edge_curve's C(0) to its C(1) as
  /// edge_end computes it (the largest over its Bezier control points, whose hull holds the edge; a little
  /// larger, for rounding): the distance to the chord less this bounds the edge's distance from below,
  /// tightly beside a nearly straight edge, where the sphere's is 0 over most of the face.
  std::array<double, 4> edge_bulge{};
  /// Each edge's curve C(t) = sum_k edge_curve[e][k] t^k, t in [0, 1] along the edge's free parameter
  /// (quadratic for quad8 and tri6, cubic for the Gregory patch).
  std::array<std::array<Vec3, 4>, 4> edge_curve{};
  /// A Gregory patch's bounds (the header), split along the unit normal at its centre and across it.
  struct GregoryBounds {
    Vec3 normal = Vec3::Zero();
    Vec3 centre = Vec3::Zero();       ///< the mean of the 20 control points
    double below = 0.0, above = 0.0;  ///< their range along normal, relative to centre
    double across = 0.0;              ///< their largest distance across normal from centre
    std::array<double, 6> second{};   ///< |P_ss.n|, |P_ss across|, the same for P_st, then P_tt
  } gregory;
  std::array<Vec3, 8> curvature{};   ///< v_k: quad8 P_ss at t = -1, 1, P_tt at s = -1, 1, P_st at the
                                     ///< corners; tri6 P_ss, P_st, P_tt
  std::array<double, 8> lo{}, hi{};  ///< the range of Q.v_k over the relative control points Q
  /// The face (relative) evaluated at a fresh run's first iterate, the centre of its domain: every fresh run
  /// on the face starts there, so its first evaluation is made once per face (the same bits).
  geometry::SurfacePoint at_centre{};
  double lambda_floor = 0.0;  ///< lower bound of lambda_min(J^T J) over the face; 0: no certificate
  double length = 0.0;        ///< the face's characteristic length (the reference's tolerances use it)

  /// The bounds for a quad8 / tri6 face (world or working units); lambda_floor 0 where the face is folded,
  /// degenerate (as the reference calls it) or not finite (then every slave takes the reference).
  static CurvedCertificate prepare(const geometry::SerendipityQuad& face);
  static CurvedCertificate prepare(const geometry::QuadraticTriangle& face);
  /// `c` made the certificate of the Gregory patch of a quad4 on `nodes` and its node normals `normals`,
  /// built relative to nodes[0] exactly as the reference builds it (closest_on_face's); the caller has found
  /// the world configuration sound (geometry::surface_defect). In place: a search prepares every face of
  /// every state. lambda_floor 0 where the patch does not exist, the face is degenerate or the bounds give
  /// nothing. `room`: uninitialised storage for one GregoryPatch that outlives `c` (the patch is built there
  /// and `c.face` points to it).
  static void prepare_gregory(CurvedCertificate& c, void* room, const std::array<Vec3, 4>& nodes,
                              const std::array<Vec3, 4>& normals);

  /// True when f is certified strictly convex on the face for `relative` (S minus origin).
  [[nodiscard]] bool convex_for(const Vec3& relative) const;
  /// A lower bound of the distance from `relative` (S minus origin) to edge e by its chord: the distance to
  /// the segment from C(0) to C(1), less edge_bulge[e].
  [[nodiscard]] double chord_bound(std::size_t e, const Vec3& relative) const;

  /// The closest point of the face to `slave` as projection::closest_point_on_serendipity_quad (or
  /// closest_point_on_quadratic_triangle, or closest_point_on_face for a Gregory patch) would report it
  /// (point in the caller's coordinates, location, normal, distance), when the certificate holds and the
  /// Newton run ends on a certified point; nothing otherwise. `start`: the first iterate (the centre when
  /// null). `options`: the reference's tolerances. `convex_checked`: the caller has found convex_for true
  /// for this slave (it is not tested again).
  [[nodiscard]] std::optional<projection::FaceClosestPoint> closest_point(
      const Vec3& slave, const projection::ProjectionOptions& options,
      const std::array<double, 2>* start = nullptr, bool convex_checked = false) const;
  /// The same into `out` (true), written where the caller keeps it (BilinearCertificate's); false: nothing
  /// certified (`out` then holds no answer).
  bool closest_point(const Vec3& slave, const projection::ProjectionOptions& options,
                     const std::array<double, 2>* start, bool convex_checked,
                     projection::FaceClosestPoint& out) const;
};

/// The certificates of one state's curved faces, each prepared on its first use: a face no slave reaches is
/// never prepared and its memory never touched (a master's curved faces are mostly far from the slaves, and
/// a certificate holds about 1.5 KB). Safe from any number of threads; the answers do not depend on which one
/// prepares a face.
class CurvedCertificates {
 public:
  CurvedCertificates() = default;
  /// Room for `faces` certificates, none prepared.
  explicit CurvedCertificates(std::size_t faces) { reset(faces); }

  /// Room for `faces` with the certificates prepared so far kept (the same faces, unmoved since): forget()
  /// those of the faces that have moved. Where the storage is too small, none is kept.
  void keep(std::size_t faces) {
    if (faces > capacity_) {
      reset(faces);
      return;
    }
    slots_.reset(faces);
    patches_.reset(faces);
  }
  /// Face f's certificate made again on its next use.
  void forget(std::size_t f) { state_[f].store(kEmpty, std::memory_order_relaxed); }

  /// None prepared, room for `faces`: the storage kept where it is large enough.
  void reset(std::size_t faces) {
    if (faces > capacity_) {
      state_.reset(new std::atomic<std::uint8_t>[faces]());
      capacity_ = faces;
    } else {
      for (std::size_t f = 0; f < faces; ++f) state_[f].store(kEmpty, std::memory_order_relaxed);
    }
    slots_.reset(faces);
    patches_.reset(faces);
  }

  [[nodiscard]] bool empty() const { return slots_.empty(); }

  /// Face f's certificate, made by prepare(CurvedCertificate&, void* room) (given a default one, and face f's
  /// room for a Gregory patch) on the first call for f; a thread asking while another prepares it waits for
  /// it (and prepares it itself where that one threw).
  template <class Prepare>
  const CurvedCertificate& get(std::size_t f, Prepare&& prepare) const {
    std::atomic<std::uint8_t>& state = state_[f];
    for (;;) {
      std::uint8_t seen = state.load(std::memory_order_acquire);
      if (seen == kReady) break;
      if (seen == kEmpty && state.compare_exchange_strong(seen, kPreparing, std::memory_order_acq_rel)) {
        try {
          prepare(slots_.construct(f), patches_.room(f));
        } catch (...) {
          state.store(kEmpty, std::memory_order_release);  // another caller may prepare it again
          throw;
        }
        state.store(kReady, std::memory_order_release);
        break;
      }
      std::this_thread::yield();  // another thread is preparing it
    }
    return slots_[f];
  }

 private:
  static constexpr std::uint8_t kEmpty = 0, kPreparing = 1, kReady = 2;
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
  std::size_t capacity_ = 0;
  mutable FaceSlots<CurvedCertificate> slots_;  ///< constructed by get(), under state_'s protocol
  /// The Gregory faces' patches, each built in its room by the preparation of its face's certificate (pages
  /// of other faces' rooms never touched).
  mutable FaceSlots<geometry::GregoryPatch> patches_;
};

}  // namespace contactnn::contact
