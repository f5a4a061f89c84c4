#include "search/flop_count.hpp"

#include "core/error.hpp"

namespace contactnn::search {

namespace {

// canonical_frame.h, cnn_cf_lane, per query. Finite test 15 x (mul + add); S - X 12; |S - X|^2 4 x 5; the
// nearest-node tie 6; the two edges 6 and their lengths 12, reciprocals 2; the |AB| = |AD| tie (two cross
// products 18, two lengths 14, the ties 6) 38; frame: e1 3, normal 9, its square 5, thresholds 3,
// Gram-Schmidt 11, normalisation 7, e2 9; C, D, S into the frame 51; orientation 2; collapsed-segment test
// (six squared distances 25, noise 5, area 15, four corner folds 40) 85; scale 1.
constexpr double kCanonical =
    29 + 12 + 20 + 6 + 6 + 12 + 2 + 38 + 3 + 9 + 5 + 3 + 11 + 7 + 9 + 51 + 2 + 85 + 1;
// Gregory normals: finite test 24, squared lengths 20, rotation 4 x 3 x 5 = 60, side tests 12, slopes (4
// divisions, 8 multiplies) 12, oriented copies 12.
constexpr double kCanonicalNormals = 24 + 20 + 60 + 12 + 12 + 12;
// cnn_domain_lane: feature ranges 2 per feature; limits 3; |AD| 4; nearest node 28; segment test (2 square
// roots) 14; four corners of cross products and the convexity test 4 x 31.
constexpr double kDomainPerFeature = 2;
constexpr double kDomain = 3 + 4 + 28 + 14 + 4 * 31;
// Angle bounds 4 x 13 (a square root each); node-normal tilts 4 x 32 (a square root each).
constexpr double kDomainAngles = 4 * 13;
constexpr double kDomainTilts = 4 * 32;
// canonical_frame.h's float pass for a float network on bilinear segments (cnn_cff_block, cnn_cff_lane), per
// query: in double the nodes relative to S and their scaling by a power of two 24; in float the finite test
// 12, |X - S|^2 20, the margin 3, the edges and C - A 9 and their squares 10, scale 2, e1 3, normal 9 and its
// square 5, Gram-Schmidt 18, e2 9, the eight features 48, extent, conditioning and error bound 8, the noise
// test 3, orientation 2, six squared distances 25 and their margin 3, four corner products 25 and their
// bounds 25, area 4, the decisions 15 (258); its domain test: feature ranges 4 per feature, limits and |AD|
// 17, nearest node 28 and the error bounds of the tests 30, segment test 20, convexity 20 (115 + 4 per
// feature). The lanes it leaves to the double pass (about 2 in 100 of random queries of the paper's domain)
// are not counted.
constexpr double kFloatFrameDouble = 24, kFloatFrame = 258, kFloatDomain = 115, kFloatDomainPerFeature = 4;
// network_block.hpp: input scaling 3 per input (in the network's type); output scaling 3 per output and the
// map back 4 (double); per unit the threshold 1 and 2 per weight; the sigmoid 27 (-gain u 1, exp's reduction
// 7 and polynomial 15, the scaling multiply 1, 1 + e 1, the division 1, clamps not counted).
constexpr double kInputScaling = 3, kOutputScaling = 3, kMapBack = 4, kSigmoid = 27;
// surface_block.hpp: the queries relative to S (finite test 2 per value, 12 differences).
constexpr double kRelativePerValue = 2, kRelative = 12;
// Bilinear: coefficients a0..a3 from the diagonals' sums and differences 36; the lane's canonical order
// (LaneSwap::choose: two keys 8, the choice 1; the swap only selects) 9; the squared distance to the
// nearest node (gap_at's cap) 23; the collapsed-segment test (edges and diagonals 18, their squared lengths
// 30, thresholds 3, area 15, four corner folds 4 x 19) 142. One hybrid (safeguarded) Newton step on the
// surface's values: evaluation 31, residual and Jacobian 33, solve (determinant 3, reciprocal 1, step 8) 12,
// update and checks 7. A plain step (lean_newton, converged_newton) on the polynomial system of
// PlainSystem<BilinearBlock>: its nine dot products once per query 46; per step u v and the doubled
// coefficients 3, g00 and g11 8, the residual 14, h01 7, then the solve 12 and update and checks 7.
constexpr double kBilinearCoefficients = 36, kCanonicalOrder = 9, kNearestNode = 23, kCollapsedTest = 142;
constexpr double kBilinearBuild = kBilinearCoefficients + kCanonicalOrder + kNearestNode + kCollapsedTest;
constexpr double kBilinearStep = 31 + 33 + 12 + 7;
constexpr double kBilinearPlainSetup = 46, kBilinearPlainStep = 3 + 8 + 14 + 7 + 12 + 7;
// Closed form: q, n, |n|^2 17; three triple products 43 and their division by |n|^2 3; discriminant, root and
// the two roots 11; the plane projections 13; xi for each root 2 x 33; the degeneracy test 12.
constexpr double kClosedForm = 17 + 43 + 3 + 11 + 13 + 66 + 12;
// four_triangles (four_triangles_block.hpp): the nodes relative to O 12; 2 (S - O) 3 and the five points'
// keys 5 x 8; S - O crossed with each node 4 x 9; per edge (4 outer, 4 spokes) the direction and S - X 6,
// |e|^2 and the projection 10 and t 1, the point 6, its key 8, (xi, eta) 4: 8 x 35; per triangle n 9, |n|^2
// 5, the two edge lengths 13, 1 / |n|^2 1, the barycentric coordinates 14, the planarity test 2, (xi, eta) 6,
// the point 9 and its key 8: 4 x 67; then N 15, S - P 3, its length 6, its side of N 5, the status test 2.
constexpr double kFourTriangles = 12 + 3 + 5 * 8 + 4 * 9 + 8 * 35 + 4 * 67 + 15 + 3 + 6 + 5 + 2;
// Gregory patch (GregoryBlock::build): the canonical order of its corner facet (a1 and a2 24, the choice 9;
// the nodes and normals then only selected) and the nearest node 23; unit normals 4 x 14; the
// collapsed-segment test of its corner facet (which gives the longest distance) 142; per node the projected
// edges and their tests 49 (x 4); edge points 48; per edge the interior points 131 (x 4); base and delta 12.
constexpr double kGregoryBuild = 24 + 9 + kNearestNode + 56 + kCollapsedTest + 4 * 49 + 48 + 4 * 131 + 12;
// One Gregory evaluation with second derivatives: Bernstein values 54, tensor part 396, rational part 4 x 85;
// the Newton system 45 and its solve and checks 19.
constexpr double kGregoryEval = 54 + 396 + 340, kGregoryStep = kGregoryEval + 45 + 19;
// The safeguarded step on top of the evaluation: both determinants, the step cap, the acceptance test 16; the
// steps along a face of the box (two divisions) 2.
constexpr double kSafeguard = 16 + 2;
// The end of the safeguarded steps: the fold test (the normal 14, |P_s|^2 |P_t|^2 11, thresholds 3) 28 (the
// cold path of the lanes near a fold not counted); the start into the canonical parametrisation and the
// iterate back 4.
constexpr double kSafeguardEnd = 28 + 4;
// Newton to convergence, at its end: the fold test at the iterate (a first-derivative evaluation: bilinear
// 31, Gregory about two thirds of a full one; the normal 14, threshold 2).
constexpr double kFoldTest = 14 + 2;
// Gregory only: the shift of an indefinite Jacobian (both smaller eigenvalues, 2 x 8 with a square root each;
// the shift 2; the shifted diagonal and determinant 5), computed in every lane of the vectorised step.
constexpr double kGregoryShift = 23;

}  // namespace

FlopCount flops_per_query(SurfaceKind kind, const Method& method, const NetworkModel* network,
                          double newton_steps) {
  const bool gregory = kind == SurfaceKind::kGregory;
  FlopCount count;
  double& d = count.in_double;
  const double build = gregory ? kGregoryBuild : kBilinearBuild;
  const double step = gregory ? kGregoryStep : kBilinearStep;
  const double eval = gregory ? kGregoryEval : 31.0;
  const double relative = kRelative + kRelativePerValue * (gregory ? 27 : 15);
  if (method.start == Method::Start::kNetwork) {
    CONTACTNN_REQUIRE(network != nullptr, "flops of " << method.name() << " need its network");
    const int n_features = feature_count(kind);
    const geometry::DomainFilters& f = network->domain().filters;
    const bool angles = f.min_angle_degrees > 0.0 || f.max_angle_degrees < 180.0;
    double& net_type = network->is_float() ? count.in_float : d;
    if (!gregory && network->is_float() && !angles) {
      // The float pass (with or without the domain test: counted with it, as search options default to).
      d += kFloatFrameDouble;
      count.in_float += kFloatFrame + kFloatDomain + kFloatDomainPerFeature * n_features;
    } else {
      d += kCanonical + (gregory ? kCanonicalNormals : 0.0);
      d += kDomain + kDomainPerFeature * n_features + (gregory ? kDomainTilts : 0.0);
      if (angles) d += kDomainAngles;
    }
    net_type += kInputScaling * n_features;
    d += kOutputScaling * 2 + kMapBack;
    double net = 0.0;
    const auto& sizes = network->layer_sizes();
    for (std::size_t l = 0; l + 1 < sizes.size(); ++l)
      net += sizes[l + 1] * (1.0 + 2.0 * sizes[l] + kSigmoid);
    (network->is_float() ? count.in_float : d) += net;
  } else {
    d += relative + build;
    // On a Gregory patch the closed form is that of the corner facet: its coefficients too (the patch's build
    // tested it), and the map to (u, v).
    if (method.start == Method::Start::kClosedForm) {
      d += kClosedForm + 2.0 +
           (gregory ? kBilinearCoefficients + kCanonicalOrder + 4 : 0.0);  // 2: the map back
    }
    if (method.start == Method::Start::kFourTriangles) {
      CONTACTNN_REQUIRE_AS(InvalidArgument, !gregory, "four_triangles has no Gregory form");
      d += kFourTriangles;
    }
  }
  if (method.is_hybrid()) {
    // The network's start needs the surface too; then one evaluation at the start and one per step (a
    // bilinear facet is evaluated again at each iterate and once at the end instead of kept:
    // safeguarded_newton).
    if (method.start == Method::Start::kNetwork) d += relative + build;
    d += eval + kSafeguardEnd + method.newton_steps * (step + kSafeguard + (gregory ? kGregoryShift : 0.0));
    if (!gregory) d += (method.newton_steps + 1) * eval;
  } else if (method.start == Method::Start::kCentre) {
    const double steps = method.to_convergence ? newton_steps : method.newton_steps;
    d += gregory ? steps * step : kBilinearPlainSetup + steps * kBilinearPlainStep;
    d += 2.0;  // the iterate back to the caller's parametrisation
    if (method.to_convergence) d += (gregory ? 2.0 * kGregoryEval / 3.0 : 31.0) + kFoldTest;
  }
  return count;
}

namespace {

// FaceSearch (face_block.hpp), per query, by face type (tri3, tri6, quad8; N nodes, stride 3 N + 3 values).
// Build: finite test 2 per value; the offsets from S 3 N and their scaling 3 N + 1 (a reciprocal); the
// monomial coefficients per component 2 (tri3), 22 (tri6), 39 (quad8); the collapsed test (corner distances 8
// each, cross products 20 each, thresholds): tri 50, quad 200.
double face_build(FaceKind kind) {
  const int n = face_node_count(kind);
  const double values = 3.0 * n + 3.0;
  const double coefficients = kind == FaceKind::kTri3 ? 6 : (kind == FaceKind::kTri6 ? 66 : 117);
  const double collapsed = kind == FaceKind::kQuad8 ? 200 : 50;
  return 2.0 * values + 3.0 * n + 3.0 * n + 1.0 + coefficients + collapsed;
}
// The point and its derivatives (first and second) at an iterate: per component tri3 4, tri6 21, quad8 49
// (+1).
double face_eval(FaceKind kind) {
  return kind == FaceKind::kTri3 ? 12 : (kind == FaceKind::kTri6 ? 63 : 148);
}
// The point alone (a halving's distance test), per component 4, 9, 13 (+1), and its squared length 5.
double face_point(FaceKind kind) {
  return kind == FaceKind::kTri3 ? 17 : (kind == FaceKind::kTri6 ? 32 : 45);
}
// newton_system 45; the solve (determinant 3, reciprocal 1, steps 8) 12; the update 2.
constexpr double kFaceSystem = 45, kFaceSolve = 12, kFaceUpdate = 2;
// A safeguarded step adds the Gauss-Newton determinant 3, the step cap 3, the clamp 4, the point at the trial
// 1 x face_point, the noise bound 5 (a square root) and the moved test 2.
constexpr double kFaceSafeguard = 3 + 3 + 4 + 5 + 2;
// Closed forms: the corner triangle's projection (e1, e2, -A 9, five dot products 25, determinant 3,
// reciprocal 1, r and s 8, the test 3) 49; the quad's corner facet (a0..a3 48) and LocalSearch's closed form.
constexpr double kTriangleClosedForm = 49, kQuadCornerFacet = 48;
// face_network_block.hpp's canonical form: the nearest corner 8 per corner, the mirror test 16, e1 and e3 6,
// the normal 9, three lengths 18 (square roots), 1 / |AB| 1, the axes 6 + 9, each node and S into the frame
// 21; the mid-side offsets 9 each; then the features' box 2 per feature, the corrections added back 2, and
// the map back to the caller's order (tri 2, quad 32).
double face_canonical(FaceKind kind) {
  const int c = kind == FaceKind::kQuad8 ? 4 : 3;
  const int n = face_node_count(kind);
  const double closed = kind == FaceKind::kQuad8 ? kQuadCornerFacet + kClosedForm : 5;
  return 8.0 * c + 16 + 6 + 9 + 18 + 1 + 15 + 21.0 * (n + 1) + 9.0 * c + closed + 2 +
         (kind == FaceKind::kQuad8 ? 32 : 2);
}

}  // namespace

FlopCount face_flops_per_query(FaceKind kind, const Method& method, const FaceNetwork* network,
                               double newton_steps) {
  FlopCount count;
  double& d = count.in_double;
  d += face_build(kind);
  const double plain = face_eval(kind) + kFaceSystem + kFaceSolve + kFaceUpdate;
  if (method.start == Method::Start::kClosedForm) {
    d += kind == FaceKind::kQuad8 ? kQuadCornerFacet + kClosedForm : kTriangleClosedForm;
  }
  if (method.start == Method::Start::kNetwork) {
    CONTACTNN_REQUIRE(network != nullptr, "flops of " << method.name() << " need its network");
    const int features = face_feature_count(kind);
    d += face_canonical(kind) + 2.0 * features + kOutputScaling * 2;
    const NetworkModel& m = network->model();
    double net = kInputScaling * features;
    const auto& sizes = m.layer_sizes();
    for (std::size_t l = 0; l + 1 < sizes.size(); ++l)
      net += sizes[l + 1] * (1.0 + 2.0 * sizes[l] + kSigmoid);
    (m.is_float() ? count.in_float : d) += net;
  }
  if (method.is_hybrid()) {
    d += method.newton_steps * (plain + kFaceSafeguard + face_point(kind));
  } else if (method.start == Method::Start::kCentre) {
    d += (method.to_convergence ? newton_steps : method.newton_steps) * plain;
  }
  d += 6;  // ok or outside by the domain
  return count;
}

}  // namespace contactnn::search
