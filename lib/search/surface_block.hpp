// Internal to lib/search: the bilinear facet and the Gregory patch of W queries at once, as structures of
// arrays, with the slave node at the origin (every node is given relative to S). Built once per query, then
// evaluated lane by lane inside loops over the lanes that the compiler vectorises.
//
// The formulas are those of geometry::BilinearPatch and geometry::GregoryPatch (SPEC 1 and 3); the tests
// compare both to rounding. What differs is only the arrangement: one array per coordinate and lane, the
// degeneracy checks of GregoryPatch::diagnose done once while building (not twice), lengths compared squared,
// and divisions by a length replaced by products with its reciprocal.
//
// Each lane's surface is built in a canonical node order of its own, the same for each of the caller's 8 node
// orders of a segment (SPEC 4): the methods compute in its parametrisation, so that a query's arithmetic, and
// with it its status and gap, do not depend on the node order it came in. A Gregory patch takes the whole
// symmetry (LaneSymmetry); a bilinear facet only the order of xi and eta (LaneSwap), since a reflection of
// (xi, eta) changes its arithmetic by exact changes of sign alone. The public eval takes the caller's
// coordinates.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/conventions.hpp"

#if defined(__GNUC__)
#define CONTACTNN_SEARCH_INLINE [[gnu::always_inline]] inline
#else
#define CONTACTNN_SEARCH_INLINE inline
#endif
// A loop over the lanes of a block: the lanes never alias and the loop carries no dependence. (Not OpenMP's
// simd construct: GCC 12 privatises the lane body's local structures into arrays there, and then gives up.)
#if defined(__clang__)
#define CONTACTNN_LANES _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define CONTACTNN_LANES _Pragma("GCC ivdep")
#else
#define CONTACTNN_LANES
#endif

// Short loops inside a lane must be unrolled (and their small arrays scalarised) before the loop over lanes
// can vectorise.
#if defined(__clang__)
#define CONTACTNN_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define CONTACTNN_UNROLL _Pragma("GCC unroll 16")
#else
#define CONTACTNN_UNROLL
#endif

namespace contactnn::search::detail {

/// Status codes held per lane as doubles inside a block (contactnn::Status values), so that every per-lane
/// quantity of a vectorised loop has the same width.
inline constexpr double kOk = 0.0, kOutside = 1.0, kNoConvergence = 2.0, kDegenerate = 3.0, kInvalid = 4.0,
                        kOutOfDomain = 5.0;
/// Not a status of the interface: Newton to convergence stopped at a pass's cap (LocalSearch::run), the lane
/// to be computed again. Written to the caller's status array only until a later pass.
inline constexpr double kPending = 255.0;
inline constexpr Status kPendingStatus = static_cast<Status>(255);

/// A surface point and its derivatives, for one lane (P relative to S). With kSecond false, the second
/// derivatives are not computed.
struct Eval {
  double p[3], ps[3], pt[3], pss[3], pst[3], ptt[3];
  /// Set by a surface's public eval and EvalStore::load only (for gap_at): +1 or -1, the caller's normal
  /// P_s x P_t over the block's canonical one (the derivatives above are the canonical ones), and the squared
  /// distance from S to the segment's nearest node.
  double orient, reach_sq;
};

/// max and min as x86's vector instructions take them (b where either is NaN): one instruction in a
/// vectorised loop, where std::fmax is a library call that stops vectorisation.
CONTACTNN_SEARCH_INLINE double max_of(double a, double b) { return a > b ? a : b; }
CONTACTNN_SEARCH_INLINE double min_of(double a, double b) { return a < b ? a : b; }

/// x is finite: 0 * x is 0 for every finite x, NaN otherwise.
CONTACTNN_SEARCH_INLINE bool is_finite(double x) { return x * 0.0 == 0.0; }

/// The largest power of two at most x for a positive normal x (its exponent bits alone); 1 for 0, subnormals,
/// infinities and NaN.
CONTACTNN_SEARCH_INLINE double power_of_two_below(double x) {
  const std::uint64_t exponent = std::bit_cast<std::uint64_t>(x) & 0x7ff0000000000000ULL;
  const bool normal = (exponent != 0) & (exponent != 0x7ff0000000000000ULL);
  return normal ? std::bit_cast<double>(exponent) : 1.0;
}

/// W queries relative to their slave nodes: node[3 i + c][l] is coordinate c of node i (A, B, C, D) minus
/// the same coordinate of S, in units of unit[l] (where `scaled`, a power of two near the segment's size, set
/// by rescale_queries; otherwise 1: a length computed from them times unit[l] is in world units);
/// normal[3 i + c][l] the raw node normal (Gregory only; unset for a bilinear block). finite[l] is 1 when
/// every input of lane l is finite (otherwise the lane's values are replaced by a unit square, so that no NaN
/// enters the arithmetic of the other lanes' vector operations).
template <int W>
struct QueryBlock {
  double node[12][W];
  double normal[12][W];
  double finite[W];
  double unit[W];
  bool scaled;  ///< unit[] is set (rescale_queries); otherwise every unit is 1 and unit[] is not set
};

/// Loads W queries (rows of `stride` = 15 or 27 values, SPEC 6 order) starting at `raw` into raw[k][l], as
/// double, unchanged (the canonical frame works on the world coordinates as given).
template <int W, class In>
CONTACTNN_SEARCH_INLINE void load_raw(const In* rows, int stride, double (*raw)[W]) {
  for (int k = 0; k < stride; ++k) {
#pragma omp simd
    for (int l = 0; l < W; ++l)
      raw[k][l] = static_cast<double>(
          rows[static_cast<std::size_t>(l) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(k)]);
  }
}

/// The queries of a raw block relative to their slave nodes. A lane with a non-finite input gets finite[l] =
/// 0 and a unit square 1 above S in place of its values, so that no NaN runs through the other lanes'
/// arithmetic. Every loop runs over the lanes (vectorised).
template <int W>
CONTACTNN_SEARCH_INLINE void relative_queries(const double (*raw)[W], bool gregory, QueryBlock<W>& q) {
  static constexpr double kSquare[12] = {-0.5, -0.5, -1, 0.5, -0.5, -1, 0.5, 0.5, -1, -0.5, 0.5, -1};
  const int stride = gregory ? 27 : 15;
  // 0 * x summed over the values (NaN where one is not finite), in two chains of additions instead of one;
  // the last value is added apart (both strides, 15 and 27, are odd).
  double check[W], odd[W];
  for (int l = 0; l < W; ++l) check[l] = odd[l] = 0.0;
  for (int k = 0; k + 1 < stride; k += 2) {
#pragma omp simd
    for (int l = 0; l < W; ++l) {
      check[l] += raw[k][l] * 0.0;
      odd[l] += raw[k + 1][l] * 0.0;
    }
  }
#pragma omp simd
  for (int l = 0; l < W; ++l) check[l] += odd[l] + raw[stride - 1][l] * 0.0;
#pragma omp simd
  for (int l = 0; l < W; ++l) q.finite[l] = check[l] == 0.0 ? 1.0 : 0.0;
  for (int k = 0; k < 12; ++k) {
    const double* x = raw[k];
    const double* slave = raw[12 + k % 3];
    const double square = kSquare[k];
#pragma omp simd
    for (int l = 0; l < W; ++l) q.node[k][l] = check[l] == 0.0 ? x[l] - slave[l] : square;
  }
  q.scaled = false;
  if (!gregory) return;  // the bilinear facet reads no normals (filling them cost 0.7 ns a query)
  for (int k = 0; k < 12; ++k) {
    const double fallback = k % 3 == 2 ? 1.0 : 0.0;
    const double* n = raw[15 + k];
#pragma omp simd
    for (int l = 0; l < W; ++l) q.normal[k][l] = check[l] == 0.0 ? n[l] : fallback;
  }
}

/// 1 when any flag is non-zero, else 0: an integer OR over the lanes (vectorised, unlike a floating-point
/// reduction, which GCC must do in order).
template <int W>
CONTACTNN_SEARCH_INLINE double any_of(const double* flags) {
  int any = 0;
  for (int l = 0; l < W; ++l) any |= flags[l] != 0.0 ? 1 : 0;
  return any != 0 ? 1.0 : 0.0;
}

/// A length whose square and fourth power stay far inside the double range: a surface whose longest node
/// distance is outside [1 / kSaneLength, kSaneLength] reports it from build (2^64, 1.8e19).
inline constexpr double kSaneLength = 0x1p64;

/// Divides each lane's offsets by unit[l], the power of two at or below the segment's own size (its largest
/// node coordinate difference; 1 where that is 0, subnormal or not finite), for a block whose surface
/// reported a length out of range: the squares and fourth powers of lengths in the surfaces' degeneracy tests
/// and Newton's systems left the double range beyond element sizes of about 1e+-77, and every method that
/// builds the surface called a sound segment degenerate there (the labels hold from 1e-300 to 1e307). In
/// units of the segment (not of the slave's offset, which for a slave far from a small segment would make the
/// segment tiny again) every node distance is near 1. Division by a power of two is exact and every decision
/// compares quantities of the same dimension, so the results have the same bits as unscaled wherever nothing
/// under- or overflowed: a lane's answer does not depend on whether its block was scaled. Gaps are multiplied
/// back by unit[l]. Run only for such blocks (found by the surface's build, which computes the lengths
/// anyway): taking every block's largest offset up front made lean newton:5 4% slower (18.6 -> 19.3 ns
/// batched).
template <int W>
void rescale_queries(QueryBlock<W>& q) {
  double size[W], inverse[W];
  for (int l = 0; l < W; ++l) size[l] = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      for (int c = 0; c < 3; ++c) {
        const double* a = q.node[3 * i + c];
        const double* b = q.node[3 * j + c];
        for (int l = 0; l < W; ++l) size[l] = max_of(size[l], std::fabs(a[l] - b[l]));
      }
    }
  }
  for (int l = 0; l < W; ++l) {
    q.unit[l] = power_of_two_below(size[l]);
    inverse[l] = 1.0 / q.unit[l];
  }
  for (int k = 0; k < 12; ++k) {
    for (int l = 0; l < W; ++l) q.node[k][l] *= inverse[l];
  }
  q.scaled = true;
}

/// Whether the segment of lane l is collapsed as the labels judge it, for either surface
/// (geometry::is_degenerate_segment; SPEC 2: coincident nodes, zero area): two nodes within 1e-10 of the
/// longest node distance L, half the cross product of the diagonals at most 1e-12 L^2, or a corner of zero
/// angle; `longest` gets L^2. Compared squared (no square root), so a decision can differ from the
/// reference's only within a few ulps of a threshold.
template <int W>
CONTACTNN_SEARCH_INLINE bool collapsed_segment(const QueryBlock<W>& q, int l, double& longest) {
  // Edges e_i = P_{i+1} - P_i (A B C D), the diagonals C - A and D - B. Corner i has next = e_i and prev =
  // -e_{i-1}: next . prev = -(e_i . e_{i-1}), |next x prev| = |e_i x e_{i-1}|, as the reference computes
  // them.
  double e[4][3], g[2][3];
  CONTACTNN_UNROLL
  for (int c = 0; c < 3; ++c) {
    const double pa = q.node[c][l], pb = q.node[3 + c][l], pc = q.node[6 + c][l], pd = q.node[9 + c][l];
    e[0][c] = pb - pa;
    e[1][c] = pc - pb;
    e[2][c] = pd - pc;
    e[3][c] = pa - pd;
    g[0][c] = pc - pa;
    g[1][c] = pd - pb;
  }
  const auto sq = [](const double* v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; };
  const double d01 = sq(e[0]), d12 = sq(e[1]), d23 = sq(e[2]), d30 = sq(e[3]), d02 = sq(g[0]), d13 = sq(g[1]);
  longest = max_of(max_of(max_of(d01, d12), max_of(d23, d30)), max_of(d02, d13));
  const double shortest = min_of(min_of(min_of(d01, d12), min_of(d23, d30)), min_of(d02, d13));
  const double flat = 1e-24 * longest * longest;
  const auto cross_sq = [](const double* u, const double* v) {
    const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
    return x * x + y * y + z * z;
  };
  // Twice the area: |(C - A) x (D - B)|.
  bool collapsed = !(longest > 0.0) | !(shortest > 1e-20 * longest) | !(0.25 * cross_sq(g[0], g[1]) > flat);
  CONTACTNN_UNROLL
  for (int i = 0; i < 4; ++i) {
    // A corner of zero angle: next . prev > 0 and next x prev ~ 0 (a straight angle is usable).
    const double* next = e[i];
    const double* back = e[(i + 3) % 4];
    const double along = next[0] * back[0] + next[1] * back[1] + next[2] * back[2];
    collapsed = collapsed | ((along < 0.0) & !(cross_sq(next, back) > flat));
  }
  return collapsed;
}

/// |S - X|^2 for the segment's node X nearest S (lane l): no point of the segment is farther from S, so no
/// gap is larger (gap_at caps it). From the squares of the same four offsets in any node order: the same
/// bits.
template <int W>
CONTACTNN_SEARCH_INLINE double nearest_node_distance_sq(const QueryBlock<W>& q, int l) {
  double d[4];
  CONTACTNN_UNROLL
  for (int i = 0; i < 4; ++i) {
    const double x = q.node[3 * i][l], y = q.node[3 * i + 1][l], z = q.node[3 * i + 2][l];
    d[i] = x * x + y * y + z * z;
  }
  return min_of(min_of(d[0], d[1]), min_of(d[2], d[3]));
}

/// The facet coefficients of lane l in the caller's node order, a_k[c] (a0: centre - S, a1, a2, a3; SPEC 1:
/// P = a0 + s a1 + t a2 + s t a3), from sums and differences of the diagonals' nodes: pa + pc, pb + pd, pc -
/// pa, pb - pd. A symmetry of the square only permutes these and changes their signs, and addition is
/// commutative, so for any node order of the segment the coefficients are the same bits, permuted, with signs
/// changed (a1 and a2 swapped and negated, a3 negated): what LaneSymmetry::choose relies on.
template <int W>
CONTACTNN_SEARCH_INLINE void caller_facet(const QueryBlock<W>& q, int l, double (*coef)[3]) {
  CONTACTNN_UNROLL
  for (int c = 0; c < 3; ++c) {
    const double pa = q.node[c][l], pb = q.node[3 + c][l], pc = q.node[6 + c][l], pd = q.node[9 + c][l];
    const double sum_ac = pa + pc, sum_bd = pb + pd, diff_ac = pc - pa, diff_bd = pb - pd;
    coef[0][c] = 0.25 * (sum_ac + sum_bd);
    coef[1][c] = 0.25 * (diff_ac + diff_bd);
    coef[2][c] = 0.25 * (diff_ac - diff_bd);
    coef[3][c] = 0.25 * (sum_ac - sum_bd);
  }
}

/// The key by which LaneSymmetry orders and orients vectors: a fixed linear form with coefficients of no
/// special ratio, so that no vector of a real mesh (axis-aligned edges included) has the key 0 or shares the
/// key of another unless they are equal. For -v it is exactly -key(v) (each rounding is symmetric), so the
/// choices below are the same for a vector and its negation.
CONTACTNN_SEARCH_INLINE double symmetry_key(const double* v) {
  return v[0] + 0.7390851332151607 * v[1] + 0.5671432904097838 * v[2];
}

/// For each lane, the symmetry of the square (SPEC 4's 8 node orders) from the caller's parametrisation to
/// the block's canonical one: with F_s(x) = x, or R - x where sign_s = -1 (the reflection about the domain
/// centre, R = 0 for (xi, eta), 1 for (u, v); likewise F_t),
///   canonical (s', t') = (F_s(swap ? t : s), F_t(swap ? s : t)),
/// and the caller's normal P_s x P_t is orient times the canonical one. The canonical facet's coefficients
/// are a1' and a2', the caller's a1 and a2 each with the sign that makes its symmetry_key positive, the one
/// of larger key first; a3' = +-a3. Every node order of one segment gives the same a1', a2', a3'
/// (caller_facet's coefficients are permuted and negated exactly), so the canonical facet, and the node order
/// built from it (GregoryBlock), are the same bits for all 8. The choice is unique unless a key is 0 or two
/// keys are equal in magnitude: a1 = 0 or a2 = 0 or a1 = +-a2 (two nodes coincide or the diagonals are
/// parallel: a collapsed segment, degenerate for every method that builds the surface), or (never for a real
/// mesh) a vector on the key's plane; then the node orders can differ in the rounding, not more.
template <int W>
struct LaneSymmetry {
  double swap[W];               ///< 1 or 0
  double sign_s[W], sign_t[W];  ///< +1 or -1
  double orient[W];             ///< +1 or -1

  /// Chooses lane l's symmetry from the caller's facet coefficients (caller_facet) and writes the canonical
  /// a1', a2', a3' to out[0..2]. (Signs and flags as doubles, compared where used: with bool values selected
  /// and compared, GCC 12 no longer vectorised the surfaces' builds.)
  CONTACTNN_SEARCH_INLINE void choose(int l, const double (*coef)[3], double (*out)[3]) {
    const double k1 = symmetry_key(coef[1]), k2 = symmetry_key(coef[2]);
    const double w = std::fabs(k1) < std::fabs(k2) ? 1.0 : 0.0;
    const double sign_1 = k1 < 0.0 ? -1.0 : 1.0, sign_2 = k2 < 0.0 ? -1.0 : 1.0;
    const double first = w != 0.0 ? sign_2 : sign_1, second = w != 0.0 ? sign_1 : sign_2;
    const double sign_st = first * second;
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      out[0][c] = first * (w != 0.0 ? coef[2][c] : coef[1][c]);
      out[1][c] = second * (w != 0.0 ? coef[1][c] : coef[2][c]);
      out[2][c] = sign_st * coef[3][c];
    }
    swap[l] = w;
    sign_s[l] = first;
    sign_t[l] = second;
    orient[l] = w != 0.0 ? -sign_st : sign_st;
  }

  /// The caller's (s, t) -> the canonical (s', t'), in place; kReflect is R. (xi, eta): by sign_s and sign_t
  /// (a reflection of 0 gives -0 here, which only the methods' arithmetic sees).
  template <int kReflect>
  CONTACTNN_SEARCH_INLINE void to_canonical(int l, double& s, double& t) const {
    const bool w = swap[l] != 0.0;
    const double x = w ? t : s, y = w ? s : t;
    if constexpr (kReflect == 0) {
      s = sign_s[l] * x;
      t = sign_t[l] * y;
    } else {
      constexpr double r = kReflect;
      s = sign_s[l] < 0.0 ? r - x : x;
      t = sign_t[l] < 0.0 ? r - y : y;
    }
  }
  /// The canonical (s', t') -> the caller's (s, t), in place: exact for (xi, eta); for (u, v) a reflection
  /// 1 - u rounds (as SquareSymmetry::to_caller's).
  template <int kReflect>
  CONTACTNN_SEARCH_INLINE void to_caller(int l, double& s, double& t) const {
    constexpr double r = kReflect;
    const double x = sign_s[l] < 0.0 ? r - s : s, y = sign_t[l] < 0.0 ? r - t : t;  // r - x: never -0
    const bool w = swap[l] != 0.0;
    s = w ? y : x;
    t = w ? x : y;
  }
  /// For canonical node i (A, B, C, D), where the caller's node in its place lies on the caller's square:
  /// s_pos > 0 at s = +1, t_pos > 0 at t = +1 (the caller's node A at (-1, -1), B (1, -1), C (1, 1), D (-1,
  /// 1)).
  CONTACTNN_SEARCH_INLINE void caller_corner(int l, int i, double& s_pos, double& t_pos) const {
    const double x = (i == 1 || i == 2) ? 1.0 : -1.0, y = i >= 2 ? 1.0 : -1.0;  // canonical node i's corner
    const double fx = sign_s[l] * x, fy = sign_t[l] * y;
    const bool w = swap[l] != 0.0;
    s_pos = w ? fy : fx;
    t_pos = w ? fx : fy;
  }
};

/// The bilinear facet's share of LaneSymmetry: whether to swap xi and eta, nothing more. A reflection of
/// (xi, eta) needs no map: it negates a1 (or a2) and a3 exactly (caller_facet), and every method's arithmetic
/// on the facet is odd in each coordinate with its coefficients (products, sums and fused products of negated
/// values are the negated results under round-to-nearest, and every box and domain is symmetric about 0), so
/// a reflected node order gives the same bits with the signs changed. Only the order of xi and eta changes
/// the arithmetic: the canonical facet has first the coefficient of larger |symmetry_key| (LaneSymmetry's
/// choice without its signs), the same for all 8 node orders. The caller's normal P_s x P_t is orient times
/// the canonical one (a swap negates it; a reflection negates P_s or P_t, and the canonical normal with it).
template <int W>
struct LaneSwap {
  double swap[W];    ///< 1 or 0
  double orient[W];  ///< -1 where swapped, else +1

  /// Chooses lane l's order from the caller's facet coefficients (caller_facet) and writes a1', a2', a3 to
  /// out[0..2].
  CONTACTNN_SEARCH_INLINE void choose(int l, const double (*coef)[3], double (*out)[3]) {
    const double k1 = symmetry_key(coef[1]), k2 = symmetry_key(coef[2]);
    const double w = std::fabs(k1) < std::fabs(k2) ? 1.0 : 0.0;
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      out[0][c] = w != 0.0 ? coef[2][c] : coef[1][c];
      out[1][c] = w != 0.0 ? coef[1][c] : coef[2][c];
      out[2][c] = coef[3][c];
    }
    swap[l] = w;
    orient[l] = w != 0.0 ? -1.0 : 1.0;
  }
  /// The caller's (xi, eta) -> the canonical, in place (a swap: exact).
  template <int kReflect>
  CONTACTNN_SEARCH_INLINE void to_canonical(int l, double& s, double& t) const {
    static_assert(kReflect == 0, "the bilinear facet's coordinates (xi, eta)");
    const bool w = swap[l] != 0.0;
    const double x = w ? t : s, y = w ? s : t;
    s = x;
    t = y;
  }
  /// The canonical (xi, eta) -> the caller's, in place.
  template <int kReflect>
  CONTACTNN_SEARCH_INLINE void to_caller(int l, double& s, double& t) const {
    to_canonical<kReflect>(l, s, t);
  }
};

/// The value of the caller's node at (s_pos, t_pos) of its square (caller_corner), among its nodes' values a,
/// b, c, d.
CONTACTNN_SEARCH_INLINE double caller_node_value(double s_pos, double t_pos, double a, double b, double c,
                                                 double d) {
  return s_pos > 0.0 ? (t_pos > 0.0 ? c : b) : (t_pos > 0.0 ? d : a);
}

// ---------------------------------------------------------------------------------------------------------
// Bilinear facet: P = a0 + s a1 + t a2 + s t a3 (geometry::BilinearPatch).

template <int W>
struct BilinearBlock {
  static constexpr SurfaceKind kKind = SurfaceKind::kBilinear;
  static constexpr bool kHasPureSecond = false;  // P_ss = P_tt = 0
  static constexpr int kReflect = 0;             // the reflections of (xi, eta): x -> -x
  double a[12][W];  // a0 xyz, a1 xyz, a2 xyz, a3 xyz, of the canonical facet (LaneSwap)
  LaneSwap<W> sym;
  double longest[W];   ///< the longest node distance, squared (build with kCheck)
  double reach_sq[W];  ///< nearest_node_distance_sq (build with kCheck)

  /// Builds the facet of every lane in its canonical parametrisation (LaneSymmetry) and sets status[l] =
  /// kDegenerate where the segment is collapsed (collapsed_segment). The facet exists for any four nodes, and
  /// Newton from the centre reported a point of such a segment ok (A = B: ok at K = 1 and 3). Returns whether
  /// a lane's longest node distance lies outside [1 / kSaneLength, kSaneLength] (a degenerate lane's too):
  /// the caller then rescales the block (rescale_queries) and builds it again, so that the fourth powers stay
  /// in the double range. kCheck false: the facet alone (a Gregory patch's corner facet, whose patch has made
  /// both tests), status not read.
  template <bool kCheck = true>
  [[nodiscard]] bool build(const QueryBlock<W>& q, double* status) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      double coef[4][3], canonical[3][3];
      caller_facet(q, l, coef);
      sym.choose(l, coef, canonical);
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        a[c][l] = coef[0][c];
        a[3 + c][l] = canonical[0][c];
        a[6 + c][l] = canonical[1][c];
        a[9 + c][l] = canonical[2][c];
      }
    }
    if constexpr (!kCheck) return false;
    double out_of_range[W];
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      double longest_sq;
      const bool collapsed = collapsed_segment(q, l, longest_sq);
      status[l] = collapsed ? kDegenerate : status[l];
      longest[l] = longest_sq;
      reach_sq[l] = nearest_node_distance_sq(q, l);
      constexpr double kSaneSquare = kSaneLength * kSaneLength;
      out_of_range[l] = (longest_sq >= 1.0 / kSaneSquare) & (longest_sq <= kSaneSquare) ? 0.0 : 1.0;
    }
    return any_of<W>(out_of_range) != 0.0;  // a loop of its own: in the lane loop it stops vectorisation
  }

  /// The point and its derivatives at the canonical (s', t') (the methods' own iterates).
  template <bool kSecond = true>
  CONTACTNN_SEARCH_INLINE void eval_canonical(int l, double s, double t, Eval& e) const {
    const double st = s * t;
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      const double a0 = a[c][l], a1 = a[3 + c][l], a2 = a[6 + c][l], a3 = a[9 + c][l];
      e.p[c] = a0 + s * a1 + t * a2 + st * a3;
      e.ps[c] = a1 + t * a3;
      e.pt[c] = a2 + s * a3;
      e.pst[c] = a3;
    }
  }

  /// At the caller's (s, t): the canonical point and derivatives there, with e.orient and e.reach_sq (build
  /// with kCheck) for gap_at. The map is exact for (xi, eta).
  template <bool kSecond = true>
  CONTACTNN_SEARCH_INLINE void eval(int l, double s, double t, Eval& e) const {
    sym.template to_canonical<kReflect>(l, s, t);
    eval_canonical<kSecond>(l, s, t, e);
    e.orient = sym.orient[l];
    e.reach_sq = reach_sq[l];
  }
  /// The methods report their canonical iterates through here (to_caller): exact for (xi, eta), nothing kept.
  CONTACTNN_SEARCH_INLINE void report(int l, double& s, double& t) {
    sym.template to_caller<kReflect>(l, s, t);
  }
};

// ---------------------------------------------------------------------------------------------------------
// Gregory patch (geometry::GregoryPatch, SPEC 3: Puso & Laursen 2002, Chiyokura & Kimura 1983).

/// Cubic Bernstein values and their first and second derivatives at t.
struct Bernstein {
  double b[4], d1[4], d2[4];
};
CONTACTNN_SEARCH_INLINE Bernstein bernstein(double t) {
  const double s = 1.0 - t;
  return Bernstein{{s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t},
                   {-3.0 * s * s, 3.0 * s * (1.0 - 3.0 * t), 3.0 * t * (2.0 - 3.0 * t), 3.0 * t * t},
                   {6.0 * s, 6.0 * (3.0 * t - 2.0), 6.0 * (1.0 - 3.0 * t), 6.0 * t}};
}

template <int W>
struct GregoryBlock {
  static constexpr SurfaceKind kKind = SurfaceKind::kGregory;
  static constexpr bool kHasPureSecond = true;
  static constexpr int kReflect = 1;  // the reflections of (u, v): x -> 1 - x
  /// P = sum B_i(u) B_j(v) base_ij + sum_interior B_i B_j w_ij delta_ij: base holds P_ij with P_ij1 in the
  /// four interior slots, delta = P_ij0 - P_ij1 in the order 11, 21, 12, 22, w_ij = s / (s + t) (Eqs 28-31).
  /// Of the patch in the lane's canonical node order (LaneSymmetry: that of its corner facet).
  double base[48][W];   // point i + 4 j, coordinate c at [3 (i + 4 j) + c]
  double delta[12][W];  // interior k, coordinate c at [3 k + c]
  LaneSymmetry<W> sym;
  double longest[W];   ///< the longest node distance, squared
  double reach_sq[W];  ///< nearest_node_distance_sq
  /// The last canonical iterate each lane reported (report) and the caller's coordinates it became: eval at
  /// those coordinates evaluates at that iterate, not at its reflection 1 - (1 - u), which may differ in the
  /// last bit (and a gap with it, by up to eps times the slave's distance). NaN: none.
  double reported[4][W];

  /// Builds the patch of every lane and sets status[l] = kDegenerate where the labels refuse it: a collapsed
  /// segment (collapsed_segment), or where GregoryPatch::diagnose would refuse it: a node normal of zero
  /// length, or an edge whose projection on an end's tangent plane is not longer than 1e-8 of the longest
  /// node distance (coincident nodes, a normal along an edge). Returns whether a lane's longest node distance
  /// lies outside [1 / kSaneLength, kSaneLength], as BilinearBlock::build.
  [[nodiscard]] bool build(const QueryBlock<W>& q, double* status) {
    // One loop: each lane's symmetry (LaneSymmetry, from its corner facet), then its patch from its nodes and
    // normals in the canonical order, selected where build_lane reads them, the same bits for every node
    // order of the segment (copied first into arrays of canonical nodes, their stores, loads and spills cost
    // the closed form and newton:1 2% more).
    double out_of_range[W];
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      double coef[4][3], canonical[3][3];
      caller_facet(q, l, coef);
      sym.choose(l, coef, canonical);
      reach_sq[l] = nearest_node_distance_sq(q, l);
      out_of_range[l] = build_lane(q, l, status);
    }
    for (int k = 0; k < 4; ++k) {
      for (int l = 0; l < W; ++l) reported[k][l] = std::numeric_limits<double>::quiet_NaN();
    }
    return any_of<W>(out_of_range) != 0.0;  // a loop of its own: in the lane loop it stops vectorisation
  }

  /// One lane's patch from its nodes and normals in its canonical order (sym, chosen), selected from q's (the
  /// collapsed test reads q as it is, the same for any node order).
  CONTACTNN_SEARCH_INLINE double build_lane(const QueryBlock<W>& q, int l, double* status) {
    double x[4][3], n0[4][3], u[4][3], pn[4][3], pp[4][3], inv_pn[4], inv_pp[4], dot_np[4];
    bool bad = false;
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      double s_pos, t_pos;
      sym.caller_corner(l, i, s_pos, t_pos);
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        x[i][c] = caller_node_value(s_pos, t_pos, q.node[c][l], q.node[3 + c][l], q.node[6 + c][l],
                                    q.node[9 + c][l]);
        n0[i][c] = caller_node_value(s_pos, t_pos, q.normal[c][l], q.normal[3 + c][l], q.normal[6 + c][l],
                                     q.normal[9 + c][l]);
      }
    }
    // Unit normals: scaled by their largest component first, so that any positive length works; a normal
    // whose components are all below 2^-900 (subnormal lengths included, whose reciprocal overflows) is first
    // multiplied by 2^600, exactly.
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      const double n0x = n0[i][0], n0y = n0[i][1], n0z = n0[i][2];
      const double m0 = max_of(max_of(std::fabs(n0x), std::fabs(n0y)), std::fabs(n0z));
      const double up = m0 < 0x1p-900 ? 0x1p600 : 1.0;
      const double nx = n0x * up, ny = n0y * up, nz = n0z * up;
      const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
      const double m = ax < ay ? (ay < az ? az : ay) : (ax < az ? az : ax);
      bad = bad | !(m > 0.0);
      const double inv_m = 1.0 / (m > 0.0 ? m : 1.0);
      const double tx = nx * inv_m, ty = ny * inv_m, tz = nz * inv_m;
      const double inv_len = 1.0 / std::sqrt(tx * tx + ty * ty + tz * tz);
      u[i][0] = tx * inv_len;
      u[i][1] = ty * inv_len;
      u[i][2] = tz * inv_len;
    }
    // A collapsed segment (its corner nodes' facet) is degenerate, as the labels judge it for either surface:
    // the patch's own tests below pass four nodes on a line with normals across it, and Newton then answered
    // ok or outside on a segment of zero area. Also gives the longest node distance, for the edge test.
    double longest_sq;
    bad = bad | collapsed_segment(q, l, longest_sq);
    longest[l] = longest_sq;
    // Each node's edges projected onto its tangent plane: pn towards the next node, pp towards the previous.
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      const int next = (i + 1) % 4, prev = (i + 3) % 4;
      double cn[3], cp[3];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        cn[c] = x[next][c] - x[i][c];
        cp[c] = x[prev][c] - x[i][c];
      }
      const double an = u[i][0] * cn[0] + u[i][1] * cn[1] + u[i][2] * cn[2];
      const double ap = u[i][0] * cp[0] + u[i][1] * cp[1] + u[i][2] * cp[2];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        pn[i][c] = cn[c] - an * u[i][c];
        pp[i][c] = cp[c] - ap * u[i][c];
      }
      const double pn_sq = pn[i][0] * pn[i][0] + pn[i][1] * pn[i][1] + pn[i][2] * pn[i][2];
      const double pp_sq = pp[i][0] * pp[i][0] + pp[i][1] * pp[i][1] + pp[i][2] * pp[i][2];
      bad = bad | !(pn_sq > 1e-16 * longest_sq) | !(pp_sq > 1e-16 * longest_sq);
      inv_pn[i] = 1.0 / std::sqrt(pn_sq);
      inv_pp[i] = 1.0 / std::sqrt(pp_sq);
      dot_np[i] = pn[i][0] * pp[i][0] + pn[i][1] * pp[i][1] + pn[i][2] * pp[i][2];
    }
    status[l] = bad ? kDegenerate : status[l];

    // Corners and edge points E(X->Y) = X + (1/3)(I - n n^T)(Y - X).
    constexpr double third = 1.0 / 3.0;
    constexpr int corner[4] = {0, 3, 15, 12};       // A, B, C, D
    constexpr int toward_next[4] = {1, 7, 14, 8};   // P10, P31, P23, P02: E(A->B), E(B->C), E(C->D), E(D->A)
    constexpr int toward_prev[4] = {4, 2, 11, 13};  // P01, P20, P32, P13: E(A->D), E(B->A), E(C->B), E(D->C)
    // Interior points: edge k (X = k, Y = k + 1) gives the point near X and the one near Y (SPEC 3); the slot
    // is base (P_ij1) or delta's P_ij0 (stored first in `interior0`, combined below).
    double interior0[4][3], interior1[4][3];  // P_ij0 and P_ij1 in the order 11, 21, 12, 22
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        base[3 * corner[i] + c][l] = x[i][c];
        base[3 * toward_next[i] + c][l] = x[i][c] + third * pn[i][c];
        base[3 * toward_prev[i] + c][l] = x[i][c] + third * pp[i][c];
      }
    }
    CONTACTNN_UNROLL
    for (int k = 0; k < 4; ++k) {
      const int y = (k + 1) % 4;
      double chord[3], a0[3], a3[3], c0[3], c1[3], c2[3], b0[3], b3[3];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) chord[c] = x[y][c] - x[k][c];
      // a0 = unit(n_X x (Y - X)): |n_X x chord| is the length of chord's projection pn[k]; likewise a3 with
      // |n_Y x chord| = |pp[y]|.
      a0[0] = (u[k][1] * chord[2] - u[k][2] * chord[1]) * inv_pn[k];
      a0[1] = (u[k][2] * chord[0] - u[k][0] * chord[2]) * inv_pn[k];
      a0[2] = (u[k][0] * chord[1] - u[k][1] * chord[0]) * inv_pn[k];
      a3[0] = (u[y][1] * chord[2] - u[y][2] * chord[1]) * inv_pp[y];
      a3[1] = (u[y][2] * chord[0] - u[y][0] * chord[2]) * inv_pp[y];
      a3[2] = (u[y][0] * chord[1] - u[y][1] * chord[0]) * inv_pp[y];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        c0[c] = third * pn[k][c];   // y1 - y0
        c2[c] = -third * pp[y][c];  // y3 - y2
        c1[c] = chord[c] - c0[c] - c2[c];
        b0[c] = third * pp[k][c];  // E(X->X') - X
        b3[c] = third * pn[y][c];  // E(Y->Y') - Y
      }
      const double k0 = a0[0] * b0[0] + a0[1] * b0[1] + a0[2] * b0[2];
      const double k1 = a3[0] * b3[0] + a3[1] * b3[1] + a3[2] * b3[2];
      // h0 = (c0.b0)/(c0.c0) = (pn[k].pp[k]) / |pn[k]|^2; h1 = (c2.b3)/(c2.c2) = -(pp[y].pn[y]) / |pp[y]|^2.
      const double h0 = dot_np[k] * inv_pn[k] * inv_pn[k];
      const double h1 = -dot_np[y] * inv_pp[y] * inv_pp[y];
      double near_x[3], near_y[3];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        const double b1 = third * ((k0 + k1) * a0[c] + k0 * a3[c] + 2.0 * h0 * c1[c] + h1 * c0[c]);
        const double b2 = third * ((k0 + k1) * a3[c] + k1 * a0[c] + 2.0 * h1 * c1[c] + h0 * c2[c]);
        near_x[c] = x[k][c] + c0[c] + b1;
        near_y[c] = x[y][c] - c2[c] + b2;
      }
      // Edge AB: P110, P210; BC: P211, P221; CD: P220, P120; DA: P121, P111 (order 11, 21, 12, 22).
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        switch (k) {
          case 0:
            interior0[0][c] = near_x[c];
            interior0[1][c] = near_y[c];
            break;
          case 1:
            interior1[1][c] = near_x[c];
            interior1[3][c] = near_y[c];
            break;
          case 2:
            interior0[3][c] = near_x[c];
            interior0[2][c] = near_y[c];
            break;
          default:
            interior1[2][c] = near_x[c];
            interior1[0][c] = near_y[c];
            break;
        }
      }
    }
    constexpr int interior_slot[4] = {5, 6, 9, 10};  // P11, P21, P12, P22
    CONTACTNN_UNROLL
    for (int k = 0; k < 4; ++k) {
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        base[3 * interior_slot[k] + c][l] = interior1[k][c];
        delta[3 * k + c][l] = interior0[k][c] - interior1[k][c];
      }
    }
    constexpr double kSaneSquare = kSaneLength * kSaneLength;
    return (longest_sq >= 1.0 / kSaneSquare) & (longest_sq <= kSaneSquare) ? 0.0 : 1.0;
  }

  /// At the caller's (u, v): the canonical point and derivatives there (the reported iterate itself where
  /// (u, v) is what it became), with e.orient and e.reach_sq for gap_at.
  template <bool kSecond = true>
  CONTACTNN_SEARCH_INLINE void eval(int l, double uu, double vv, Eval& e) const {
    const bool known = (uu == reported[2][l]) & (vv == reported[3][l]);
    double cu = uu, cv = vv;
    sym.template to_canonical<kReflect>(l, cu, cv);
    eval_canonical<kSecond>(l, known ? reported[0][l] : cu, known ? reported[1][l] : cv, e);
    e.orient = sym.orient[l];
    e.reach_sq = reach_sq[l];
  }
  /// The methods report their canonical iterates through here: (u, v) becomes the caller's, and both are kept
  /// for eval.
  CONTACTNN_SEARCH_INLINE void report(int l, double& uu, double& vv) {
    reported[0][l] = uu;
    reported[1][l] = vv;
    sym.template to_caller<kReflect>(l, uu, vv);
    reported[2][l] = uu;
    reported[3][l] = vv;
  }

  /// Position and derivatives at the canonical (u, v) for lane l: GregoryPatch::evaluate, quotient rule
  /// included; a rational weight whose denominator is below 1e-14 in magnitude is 1/2 with zero derivatives
  /// (SPEC 3).
  template <bool kSecond = true>
  CONTACTNN_SEARCH_INLINE void eval_canonical(int l, double uu, double vv, Eval& e) const {
    const Bernstein bu = bernstein(uu), bv = bernstein(vv);
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      e.p[c] = e.ps[c] = e.pt[c] = 0.0;
      if constexpr (kSecond) e.pss[c] = e.pst[c] = e.ptt[c] = 0.0;
    }
    CONTACTNN_UNROLL
    for (int j = 0; j < 4; ++j) {
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        const double q0 = base[3 * (4 * j) + c][l], q1 = base[3 * (4 * j + 1) + c][l];
        const double q2 = base[3 * (4 * j + 2) + c][l], q3 = base[3 * (4 * j + 3) + c][l];
        const double r = bu.b[0] * q0 + bu.b[1] * q1 + bu.b[2] * q2 + bu.b[3] * q3;
        const double r_u = bu.d1[0] * q0 + bu.d1[1] * q1 + bu.d1[2] * q2 + bu.d1[3] * q3;
        e.p[c] += bv.b[j] * r;
        e.ps[c] += bv.b[j] * r_u;
        e.pt[c] += bv.d1[j] * r;
        if constexpr (kSecond) {
          const double r_uu = bu.d2[0] * q0 + bu.d2[1] * q1 + bu.d2[2] * q2 + bu.d2[3] * q3;
          e.pss[c] += bv.b[j] * r_uu;
          e.pst[c] += bv.d1[j] * r_u;
          e.ptt[c] += bv.d2[j] * r;
        }
      }
    }
    const double s_of[2] = {uu, 1.0 - uu}, t_of[2] = {vv, 1.0 - vv};
    CONTACTNN_UNROLL
    for (int k = 0; k < 4; ++k) {
      const int a = k & 1, b = k >> 1;
      const double su = a == 0 ? 1.0 : -1.0, sv = b == 0 ? 1.0 : -1.0;
      const double s = s_of[a], t = t_of[b];
      const double den = s + t;
      const bool guard = std::fabs(den) < 1e-14;
      const double inv = 1.0 / (guard ? 1.0 : den);
      const double inv2 = inv * inv, inv3 = inv2 * inv;
      // w = s / (s + t); w_s = t/d^2, w_t = -s/d^2, w_ss = -2t/d^3, w_st = (s - t)/d^3, w_tt = 2s/d^3.
      const double w = guard ? 0.5 : s * inv;
      const double w_u = guard ? 0.0 : su * t * inv2;
      const double w_v = guard ? 0.0 : -sv * s * inv2;
      const double p = bu.b[1 + a], p1 = bu.d1[1 + a], q = bv.b[1 + b], q1 = bv.d1[1 + b];
      const double c_p = p * q * w;
      const double c_s = p1 * q * w + p * q * w_u;
      const double c_t = p * q1 * w + p * q * w_v;
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        const double dk = delta[3 * k + c][l];
        e.p[c] += c_p * dk;
        e.ps[c] += c_s * dk;
        e.pt[c] += c_t * dk;
      }
      if constexpr (kSecond) {
        const double w_uu = guard ? 0.0 : -2.0 * t * inv3;
        const double w_uv = guard ? 0.0 : su * sv * (s - t) * inv3;
        const double w_vv = guard ? 0.0 : 2.0 * s * inv3;
        const double p2 = bu.d2[1 + a], q2 = bv.d2[1 + b];
        const double c_ss = p2 * q * w + 2.0 * p1 * q * w_u + p * q * w_uu;
        const double c_st = p1 * q1 * w + p1 * q * w_v + p * q1 * w_u + p * q * w_uv;
        const double c_tt = p * q2 * w + 2.0 * p * q1 * w_v + p * q * w_vv;
        CONTACTNN_UNROLL
        for (int c = 0; c < 3; ++c) {
          const double dk = delta[3 * k + c][l];
          e.pss[c] += c_ss * dk;
          e.pst[c] += c_st * dk;
          e.ptt[c] += c_tt * dk;
        }
      }
    }
  }
};

}  // namespace contactnn::search::detail
