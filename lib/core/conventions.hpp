// The conventions of docs/spec.md (the specification), written once. Every other module takes them from here.
//
//  - Segment nodes A, B, C, D counter-clockwise seen from the side the normal points to;
//    normal direction = (B - A) x (D - A) at A (SPEC 1).
//  - Bilinear facet: (xi, eta) in [-1, 1]^2, A at (-1,-1), B at (1,-1), C at (1,1), D at (-1,1).
//  - Gregory patch: (u, v) in [0, 1]^2, P00 = A, P30 = B, P33 = C, P03 = D; on a flat segment
//    u = (xi + 1) / 2, v = (eta + 1) / 2.
//  - Gap g = n . (S - P), n the unit normal P_1 x P_2 at the solution; g < 0 is penetration (SPEC 2).
//  - Normalised frame (SPEC 4): A at the origin, B = (1, 0, 0), D in the xy-plane with y_D > 0.
//  - Matrices of samples are row-major: one row per configuration, one column per feature.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace contactnn {

/// The surface a master segment is interpolated by.
enum class SurfaceKind : std::uint8_t { kBilinear = 0, kGregory = 1 };

/// Status of every projection (SPEC section 2). Stored as its integer value in datasets; the
/// values are part of the dataset schema and never renumbered.
enum class Status : std::uint8_t {
  kOk = 0,             ///< converged, inside the parameter domain
  kOutside = 1,        ///< converged, outside the domain; coordinates are still reported
  kNoConvergence = 2,  ///< iteration limit reached without meeting the tolerances
  kDegenerate = 3,     ///< the segment or its Jacobian is unusable (coincident nodes, zero area, ...)
  kInvalid = 4,        ///< a non-finite input
  kOutOfDomain = 5,    ///< evaluate-net only: input outside the domain the network was trained on
  kNoSegment = 6,      ///< SPEC 7: the global search found no segment for the slave node (a pairs file's row
                       ///< without coordinates); nothing to compute
};
inline constexpr int kStatusCount = 7;

/// The CSV / report spelling of a status: ok, outside, no_convergence, degenerate, invalid, out_of_domain,
/// no_segment.
[[nodiscard]] std::string_view to_string(Status status);
/// Inverse of to_string; std::nullopt for an unknown name.
[[nodiscard]] std::optional<Status> status_from_string(std::string_view name);

/// "bilinear" or "gregory".
[[nodiscard]] std::string_view to_string(SurfaceKind kind);
/// Inverse of to_string; throws InvalidArgument naming the accepted values for anything else.
[[nodiscard]] SurfaceKind surface_from_string(std::string_view name);

/// Where on a master face its closest point to a slave node lies (SPEC 9): inside the face (the stationary
/// point of SPEC 2), on one of its edges, or at one of its vertices.
enum class Location : std::uint8_t { kFace = 0, kEdge = 1, kVertex = 2 };
/// "face", "edge" or "vertex" (the `location` column of SPEC 9).
[[nodiscard]] std::string_view to_string(Location location);

/// Parameter domain of a surface: [lo, hi]^2.
struct ParamDomain {
  double lo;
  double hi;
};
[[nodiscard]] constexpr ParamDomain param_domain(SurfaceKind kind) {
  return kind == SurfaceKind::kBilinear ? ParamDomain{-1.0, 1.0} : ParamDomain{0.0, 1.0};
}

/// Names of the two local coordinates as written in CSV files and reports.
[[nodiscard]] constexpr std::array<std::string_view, 2> coordinate_names(SurfaceKind kind) {
  if (kind == SurfaceKind::kBilinear) return {"xi", "eta"};
  return {"u", "v"};
}

/// Raw configuration columns of RAW.csv (SPEC 6): 15 node coordinates, then for Gregory 12 normal components.
inline constexpr std::array<std::string_view, 15> kRawPointColumns = {
    "ax", "ay", "az", "bx", "by", "bz", "cx", "cy", "cz", "dx", "dy", "dz", "sx", "sy", "sz"};
inline constexpr std::array<std::string_view, 12> kRawNormalColumns = {
    "nax", "nay", "naz", "nbx", "nby", "nbz", "ncx", "ncy", "ncz", "ndx", "ndy", "ndz"};

/// Normalised network inputs (SPEC 4). Bilinear: the first 8; Gregory: all 16
/// (node normals rotated into the frame, entered as n_x/n_z and n_y/n_z for A, B, C, D).
inline constexpr std::array<std::string_view, 16> kFeatureNames = {
    "xc", "yc", "zc", "xd", "yd", "xs", "ys", "zs", "pa", "qa", "pb", "qb", "pc", "qc", "pd", "qd"};
[[nodiscard]] constexpr int feature_count(SurfaceKind kind) {
  return kind == SurfaceKind::kBilinear ? 8 : 16;
}

/// Version of the HDF5 dataset and network schemas (docs/files.md). Bumped on any
/// incompatible change; readers reject other versions with a message naming both.
inline constexpr int kDatasetSchemaVersion = 1;
inline constexpr int kNetworkSchemaVersion = 1;
/// The `kind` attribute at the root of each contactnn HDF5 file, so a network is never read as a dataset.
inline constexpr std::string_view kDatasetFileKind = "contactnn-dataset";
inline constexpr std::string_view kNetworkFileKind = "contactnn-network";

}  // namespace contactnn
