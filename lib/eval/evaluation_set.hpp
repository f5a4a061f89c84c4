// A set of node-segment queries to judge the search methods on: world coordinates in the caller's node order,
// as an FE code hands them over, beside their reference labels. From a gen-configs dataset (the paper's grid,
// a held-out random sample, a scene's domain: placed in world coordinates) or from a labelled RAW.csv (a
// scene's pairs from gen-configs --scene, a label-mode output).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "dataset/labelled_set.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::eval {

struct EvaluationSet {
  std::string name;    ///< shown in reports: the file's stem, e.g. "bilinear", "hueeber1-pairs"
  std::string source;  ///< the file it was read from
  SurfaceKind surface = SurfaceKind::kBilinear;
  /// rows x raw_columns(surface): ax ay az ... sz (then nax ... ndz for Gregory), SPEC 6 order, world units.
  std::vector<double> raw;
  dataset::MatrixRM<double> labels;  ///< rows x 2: the reference's local coordinates in the caller's order
  std::vector<Status> label_status;  ///< the reference's status per row
  std::vector<double> label_gap;     ///< the reference gap (world units, the caller's normal); 0 without one
  /// Longest node distance of each row's segment (world units): the size gap errors are relative to.
  std::vector<double> size;
  /// The reference solver's iterations per row (datasets; -1 where the file has none).
  std::vector<int> label_iterations;
  std::int64_t skipped_no_segment = 0;  ///< pairs-file rows without a segment (SPEC 7), not queries

  [[nodiscard]] std::int64_t rows() const { return static_cast<std::int64_t>(label_status.size()); }
  [[nodiscard]] static constexpr int raw_columns(SurfaceKind kind) {
    return kind == SurfaceKind::kBilinear ? 15 : 27;
  }
};

/// The rows of a gen-configs dataset as world queries: each row's canonical configuration
/// (configuration_from_features) in the dataset's own frame, or (random_placement) moved by
/// random_placement(seed, row), a similarity that leaves the local coordinates unchanged and scales the gap.
/// Labels are the dataset's (canonical = caller order for these configurations).
[[nodiscard]] EvaluationSet set_from_dataset(const dataset::LabelledSet& set, std::string name,
                                             std::string source, bool random_placement, std::uint64_t seed);

/// The rows of a labelled RAW.csv (SPEC 6 columns, then xi,eta or u,v, status and gap as gen-configs writes
/// them: label mode or --scene). Rows with status no_segment are not queries: skipped and counted. Errors:
/// those of the RAW reader, and FormatError naming file, line and column for a missing or unparsable label
/// column or an unknown status.
[[nodiscard]] EvaluationSet set_from_labelled_csv(const std::filesystem::path& path, SurfaceKind kind);

/// Appends a configuration's SPEC 6 raw values (the nodes, the slave node, and for Gregory the normals) to
/// `raw`, as an EvaluationSet holds them.
void append_raw(std::vector<double>& raw, const geometry::Configuration& c, SurfaceKind kind);

}  // namespace contactnn::eval
