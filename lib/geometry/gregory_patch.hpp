// The Gregory patch of a 4-node segment with node normals (paper Eqs 24-31; SPEC 3).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// Why four nodes and four node normals define no Gregory patch (GregoryPatch::diagnose).
enum class GregoryDefect : std::uint8_t {
  kNone = 0,
  kNonFinite,      ///< a node or normal component is NaN or infinite
  kZeroNormal,     ///< a node normal has zero length
  kDegenerateEdge  ///< an edge of (almost) zero length, or a node normal (almost) parallel to one of its
                   ///< edges
};

/// G1 Gregory patch over a quadrilateral segment, built from its nodes and node normals as in
/// Puso & Laursen, "A 3D contact smoothing method using Gregory patches", IJNME 54 (2002) 1161-1194,
/// with the interior points of Chiyokura & Kimura, "Design of solids with free-form surfaces",
/// Computer Graphics 17(3) (1983) 289-298.
///
/// P(u, v) = sum_ij B_i^3(u) B_j^3(v) P_ij (Eq 27), (u, v) in [0,1]^2, P00 = A, P30 = B, P33 = C, P03 = D;
/// u runs A->B, v runs A->D. The four interior points are rational (Eqs 28-31):
///   P11 = (u P110 + v P111) / (u + v),          P21 = ((1-u) P210 + v P211) / ((1-u) + v),
///   P12 = (u P120 + (1-v) P121) / (u + (1-v)),  P22 = ((1-u) P220 + (1-v) P221) / ((1-u) + (1-v)).
/// P_ij0 comes from the edge along u (v = 0 or v = 1) and P_ij1 from the edge along v (u = 0 or 1), so
/// that on each boundary only the point of that edge acts (SPEC 3 gives the edge of each point).
///
/// Choices where SPEC 3 leaves room (also the contract of evaluate()):
///  - The denominators are used signed. Where |denominator| < kDenominatorGuard the rational point is
///    the mean of its two points and its derivatives are taken as zero. Inside [0,1]^2 this happens
///    only at the corners, where the point is multiplied by B_1 B_1 = 0 and the position and first
///    derivatives are the continuous limits; the second derivatives there are the values of that
///    convention (the Gregory patch is not C2 at its corners: their limit depends on the direction).
///  - Outside [0,1]^2 each denominator is zero on a line through a corner (u + v = 0, u - v = -1,
///    u - v = 1, u + v = 2); near those lines position and derivatives grow like 1/d, 1/d^2, 1/d^3 and
///    change sign across them. Evaluation stays finite, but every box larger than [0,1]^2 holds pieces of
///    these lines next to the corners (for [-0.1, 1.1]^2: u + v = 0 from (-0.1, 0.1) to (0.1, -0.1), and
///    likewise at B, C, D), so a projection that lets iterates leave [0,1]^2 must expect wild values
///    there. Away from them (|d| > 0.2, say) the patch is smooth and the derivatives are exact.
///  - The normal at corner X equals n_X when n_X points to the side of the segment's own corner normal
///    (next - X) x (prev - X); a flipped node normal flips the patch normal there.
class GregoryPatch {
 public:
  static constexpr SurfaceKind kKind = SurfaceKind::kGregory;
  /// SPEC 3: below this |denominator| a rational interior point is the mean of its two points.
  static constexpr double kDenominatorGuard = 1e-14;
  /// An edge counts as degenerate when its projection onto an end's tangent plane is shorter than
  /// this times the longest node distance (a normal within ~1e-8 rad of the edge, or coincident nodes).
  static constexpr double kMinProjectedEdgeRatio = 1e-8;

  /// @param nodes    A, B, C, D, counter-clockwise seen from the side the normal points to (SPEC 1).
  /// @param normals  node normals at A, B, C, D, any positive length (normalised here).
  /// Throws InvalidArgument naming the defect when diagnose(nodes, normals) is not kNone.
  GregoryPatch(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals);

  /// The patch of inputs the caller has found sound (diagnose(nodes, normals) == kNone), without checking
  /// them again: a search that builds each face's patch once per state diagnoses it once.
  struct Diagnosed {};
  GregoryPatch(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals, Diagnosed);

  /// kNone when the constructor accepts these inputs, otherwise the first defect found. Cheap: a caller
  /// (the projection) uses it to report `invalid` / `degenerate` instead of catching.
  /// `unit_normals`, where given, receives the normals normalised as the constructor does them (set where
  /// the result is kNone).
  [[nodiscard]] static GregoryDefect diagnose(const std::array<Vec3, 4>& nodes,
                                              const std::array<Vec3, 4>& normals,
                                              std::array<Vec3, 4>* unit_normals = nullptr);

  /// P(u, v); any finite (u, v), see the class comment for the lines outside [0,1]^2.
  [[nodiscard]] Vec3 position(double u, double v) const noexcept;

  /// Position and exact first and second derivatives in (u, v) (quotient rule on Eqs 28-31 included).
  /// d_s = dP/du, d_t = dP/dv, d_ss = d2P/du2, d_st = d2P/dudv, d_tt = d2P/dv2. No allocation.
  [[nodiscard]] SurfacePoint evaluate(double u, double v) const noexcept;

  /// What evaluate() computes on its way to the second derivatives (evaluate_first keeps it for complete()).
  struct Partial;
  /// evaluate()'s position and first derivatives alone, the same bits (its second derivatives left as they
  /// were): a Newton run that converges at (u, v) needs no more. `partial` keeps the rest of the way.
  void evaluate_first(double u, double v, Partial& partial, SurfacePoint& out) const noexcept;
  /// The second derivatives of evaluate_first's point into `out`, the same bits as evaluate()'s.
  void complete(const Partial& partial, SurfacePoint& out) const noexcept;

  /// Length scale for relative tolerances: the longest edge or diagonal (as BilinearPatch).
  [[nodiscard]] double characteristic_length() const { return characteristic_length_; }

  [[nodiscard]] const std::array<Vec3, 4>& nodes() const { return nodes_; }
  /// The node normals, normalised to unit length.
  [[nodiscard]] const std::array<Vec3, 4>& normals() const { return normals_; }

  /// The 20 control points. Index i + 4 j (0..15) holds Bezier point P_ij, where for the four interior
  /// (i, j) in {1,2}^2 it holds P_ij0; index 16 + (i-1) + 2 (j-1) holds P_ij1. So: 0 = A, 3 = B, 15 = C,
  /// 12 = D, 1 = P10, 4 = P01, 5 = P110, 6 = P210, 9 = P120, 10 = P220, 16 = P111, 17 = P211,
  /// 18 = P121, 19 = P221. Use control_index / interior_index rather than the numbers.
  [[nodiscard]] const std::array<Vec3, 20>& control_points() const { return control_; }
  /// The control points of the patch on `nodes` with unit normals `unit_normals` (each the constructor's
  /// stableNormalized() of a node normal): control_points() bit for bit, without the evaluation form (a
  /// search bounds every face of a state by them and builds the patch only for the faces it projects on).
  [[nodiscard]] static std::array<Vec3, 20> control_points_of(const std::array<Vec3, 4>& nodes,
                                                              const std::array<Vec3, 4>& unit_normals);
  /// Index of P_ij (i, j in 0..3) in control_points(); for interior (i, j) that of P_ij0.
  [[nodiscard]] static constexpr int control_index(int i, int j) { return i + 4 * j; }
  /// Index of interior point P_ijk (i, j in 1..2, k in 0..1) in control_points().
  [[nodiscard]] static constexpr int interior_index(int i, int j, int k) {
    return k == 0 ? i + 4 * j : 16 + (i - 1) + 2 * (j - 1);
  }

 private:
  /// Throws InvalidArgument naming the defect where diagnose finds one.
  static void check(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals);

  std::array<Vec3, 4> nodes_;
  std::array<Vec3, 4> normals_;
  std::array<Vec3, 20> control_;
  // Evaluation form: P = sum B_i B_j base_ij + sum_interior B_i B_j w_ij delta_ij, where base holds
  // P_ij1 in the interior slots, delta_ = P_ij0 - P_ij1 in the order 11, 21, 12, 22 and
  // w_ij = s / (s + t) is the weight of P_ij0 in Eqs 28-31. The bicubic part is kept in powers,
  // sum_ab power_[a + 4 b] u^a v^b, evaluated by Horner's rule with its derivatives (a quarter less work
  // than the Bernstein sums: Newton evaluates the patch several times per slave node).
  std::array<Vec3, 16> power_;
  std::array<Vec3, 4> delta_;
  double characteristic_length_ = 0.0;
};

// ---- evaluation, inline: Newton calls it tens of millions of times ----

namespace gregory_detail {

/// Cubic Bernstein values B_i^3(t) and their first and second derivatives.
struct Bernstein3 {
  double b[4], d1[4], d2[4];
};

inline Bernstein3 bernstein3(double t) {
  const double s = 1.0 - t;
  return Bernstein3{{s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t},
                    {-3.0 * s * s, 3.0 * s * (1.0 - 3.0 * t), 3.0 * t * (2.0 - 3.0 * t), 3.0 * t * t},
                    {6.0 * s, 6.0 * (3.0 * t - 2.0), 6.0 * (1.0 - 3.0 * t), 6.0 * t}};
}

/// w = s / (s + t) and its derivatives in (u, v), where ds/du = sign_u and dt/dv = sign_v (each +-1).
struct RationalWeight {
  double w, w_u, w_v, w_uu, w_uv, w_vv;
};

inline RationalWeight rational_weight(double s, double t, double sign_u, double sign_v) {
  const double d = s + t;
  if (std::abs(d) < GregoryPatch::kDenominatorGuard) return RationalWeight{0.5, 0.0, 0.0, 0.0, 0.0, 0.0};
  const double inv = 1.0 / d;
  const double inv2 = inv * inv;
  const double inv3 = inv2 * inv;
  // w_s = t/d^2, w_t = -s/d^2, w_ss = -2t/d^3, w_st = (s - t)/d^3, w_tt = 2s/d^3; sign_u^2 = sign_v^2 = 1.
  return RationalWeight{
      s * inv,       sign_u * t * inv2, -sign_v * s * inv2, -2.0 * t * inv3, sign_u * sign_v * (s - t) * inv3,
      2.0 * s * inv3};
}

}  // namespace gregory_detail

inline Vec3 GregoryPatch::position(double u, double v) const noexcept {
  const double su = 1.0 - u, sv = 1.0 - v;
  const double bu[4] = {su * su * su, 3.0 * u * su * su, 3.0 * u * u * su, u * u * u};
  const double bv[4] = {sv * sv * sv, 3.0 * v * sv * sv, 3.0 * v * v * sv, v * v * v};
  // The bicubic by Horner's rule, in u within each power of v, then in v: the same bits as evaluate()'s
  // bicubic part. The rational weights below are s / d, evaluate()'s s * (1 / d): the two positions may
  // differ in the last bit.
  Vec3 row[4];
  for (int b = 0; b < 4; ++b) {
    const Vec3* a = &power_[static_cast<std::size_t>(4 * b)];
    row[b] = ((a[3] * u + a[2]) * u + a[1]) * u + a[0];
  }
  Vec3 p = ((row[3] * v + row[2]) * v + row[1]) * v + row[0];
  // Eqs 28-31: (s, t) = (u, v), (1-u, v), (u, 1-v), (1-u, 1-v) for P11, P21, P12, P22.
  const double s_of[2] = {u, su}, t_of[2] = {v, sv};
  for (int k = 0; k < 4; ++k) {
    const int a = k & 1, b = k >> 1;
    const double d = s_of[a] + t_of[b];
    const double w = std::abs(d) < kDenominatorGuard ? 0.5 : s_of[a] / d;
    p += (bu[1 + a] * bv[1 + b] * w) * delta_[k];
  }
  return p;
}

struct GregoryPatch::Partial {
  double u, v;
  gregory_detail::Bernstein3 bu, bv;
  gregory_detail::RationalWeight w[4];
  Vec3 row[4], row_u[4];
};

inline void GregoryPatch::evaluate_first(double u, double v, Partial& partial,
                                         SurfacePoint& out) const noexcept {
  using gregory_detail::bernstein3;
  partial.u = u;
  partial.v = v;
  partial.bu = bernstein3(u);
  partial.bv = bernstein3(v);
  const gregory_detail::Bernstein3 &bu = partial.bu, &bv = partial.bv;
  // Polynomial part: Horner's rule in u within each power of v (the row and its u-derivative), then in v.
  Vec3* row = partial.row;
  Vec3* row_u = partial.row_u;
  for (int b = 0; b < 4; ++b) {
    const Vec3* a = &power_[static_cast<std::size_t>(4 * b)];
    row[b] = ((a[3] * u + a[2]) * u + a[1]) * u + a[0];
    row_u[b] = (3.0 * a[3] * u + 2.0 * a[2]) * u + a[1];
  }
  out.position = ((row[3] * v + row[2]) * v + row[1]) * v + row[0];
  out.d_s = ((row_u[3] * v + row_u[2]) * v + row_u[1]) * v + row_u[0];
  out.d_t = (3.0 * row[3] * v + 2.0 * row[2]) * v + row[1];
  // Rational part f = B_i(u) B_j(v) w(u, v) times delta, differentiated by the full product and quotient
  // rules.
  const double s_of[2] = {u, 1.0 - u}, t_of[2] = {v, 1.0 - v};
  const double sign[2] = {1.0, -1.0};
  for (int k = 0; k < 4; ++k) {
    const int a = k & 1, b = k >> 1;  // a: s = u or 1-u (i = 1 + a); b: t = v or 1-v (j = 1 + b)
    const gregory_detail::RationalWeight& w = partial.w[k] =
        gregory_detail::rational_weight(s_of[a], t_of[b], sign[a], sign[b]);
    const double p = bu.b[1 + a], p1 = bu.d1[1 + a];
    const double q = bv.b[1 + b], q1 = bv.d1[1 + b];
    const Vec3& dk = delta_[k];
    out.position += (p * q * w.w) * dk;
    out.d_s += (p1 * q * w.w + p * q * w.w_u) * dk;
    out.d_t += (p * q1 * w.w + p * q * w.w_v) * dk;
  }
}

inline void GregoryPatch::complete(const Partial& partial, SurfacePoint& out) const noexcept {
  const double u = partial.u, v = partial.v;
  const gregory_detail::Bernstein3 &bu = partial.bu, &bv = partial.bv;
  const Vec3* row = partial.row;
  const Vec3* row_u = partial.row_u;
  Vec3 row_uu[4];
  for (int b = 0; b < 4; ++b) {
    const Vec3* a = &power_[static_cast<std::size_t>(4 * b)];
    row_uu[b] = 6.0 * a[3] * u + 2.0 * a[2];
  }
  out.d_ss = ((row_uu[3] * v + row_uu[2]) * v + row_uu[1]) * v + row_uu[0];
  out.d_st = (3.0 * row_u[3] * v + 2.0 * row_u[2]) * v + row_u[1];
  out.d_tt = 6.0 * row[3] * v + 2.0 * row[2];
  for (int k = 0; k < 4; ++k) {
    const int a = k & 1, b = k >> 1;
    const gregory_detail::RationalWeight& w = partial.w[k];
    const double p = bu.b[1 + a], p1 = bu.d1[1 + a], p2 = bu.d2[1 + a];
    const double q = bv.b[1 + b], q1 = bv.d1[1 + b], q2 = bv.d2[1 + b];
    const Vec3& dk = delta_[k];
    out.d_ss += (p2 * q * w.w + 2.0 * p1 * q * w.w_u + p * q * w.w_uu) * dk;
    out.d_st += (p1 * q1 * w.w + p1 * q * w.w_v + p * q1 * w.w_u + p * q * w.w_uv) * dk;
    out.d_tt += (p * q2 * w.w + 2.0 * p * q1 * w.w_v + p * q * w.w_vv) * dk;
  }
}

inline SurfacePoint GregoryPatch::evaluate(double u, double v) const noexcept {
  SurfacePoint out;
  Partial partial;
  evaluate_first(u, v, partial, out);
  complete(partial, out);
  return out;
}

}  // namespace contactnn::geometry
