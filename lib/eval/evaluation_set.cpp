#include "eval/evaluation_set.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "eval/placement.hpp"
#include "geometry/bilinear_patch.hpp"
#include "io/csv.hpp"
#include "io/raw_configurations.hpp"

namespace contactnn::eval {

void append_raw(std::vector<double>& raw, const geometry::Configuration& c, SurfaceKind kind) {
  for (const auto& node : c.nodes) raw.insert(raw.end(), {node.x(), node.y(), node.z()});
  raw.insert(raw.end(), {c.slave.x(), c.slave.y(), c.slave.z()});
  if (kind == SurfaceKind::kGregory) {
    for (const auto& n : c.normals) raw.insert(raw.end(), {n.x(), n.y(), n.z()});
  }
}

EvaluationSet set_from_dataset(const dataset::LabelledSet& set, std::string name, std::string source,
                               bool random_placement, std::uint64_t seed) {
  EvaluationSet out;
  out.name = std::move(name);
  out.source = std::move(source);
  out.surface = set.surface;
  const auto n = static_cast<std::size_t>(set.size());
  out.raw.reserve(n * static_cast<std::size_t>(EvaluationSet::raw_columns(set.surface)));
  out.labels = set.labels;
  out.label_status = set.status;
  out.label_gap.resize(n);
  out.size.resize(n);
  out.label_iterations.resize(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto row = static_cast<Eigen::Index>(r);
    geometry::Configuration c = configuration_from_features(set.surface, set.features.row(row).data());
    double scale = 1.0;
    if (random_placement) {
      const Placement p = eval::random_placement(seed, r);
      c = place(c, p);
      scale = p.scale;
    }
    append_raw(out.raw, c, set.surface);
    // The dataset's gap is the canonical one in frame units (|AB| = 1); these configurations are canonical
    // (identity order, z_S >= 0), so in the caller's terms it only scales with the placement.
    out.label_gap[r] = set.gap[row] * scale / set.scale[row];
    out.size[r] = geometry::max_node_distance(c.nodes);
    out.label_iterations[r] = set.iterations[row];
  }
  return out;
}

EvaluationSet set_from_labelled_csv(const std::filesystem::path& path, SurfaceKind kind) {
  EvaluationSet out;
  out.name = path.stem().string();
  out.source = path.string();
  out.surface = kind;
  io::RawConfigurationReader reader(path, kind);
  const std::vector<std::string>& header = reader.header();
  const auto names = coordinate_names(kind);
  const auto column = [&](std::string_view name) {
    const std::optional<std::size_t> found = io::find_column(header, name, path);
    CONTACTNN_REQUIRE_AS(FormatError, found.has_value(),
                         "'" << path.string() << "': no column '" << name
                             << "': a labelled RAW.csv (gen-configs --input or --scene output) is expected");
    return *found;
  };
  const std::size_t c0 = column(names[0]), c1 = column(names[1]), c_status = column("status"),
                    c_gap = column("gap");
  std::vector<double> labels;
  io::RawChunk chunk;
  while (reader.next_chunk(chunk, io::kRawChunkRows)) {
    for (std::size_t i = 0; i < chunk.size(); ++i) {
      const io::CsvRecord& fields = chunk.records[i];
      const std::size_t line = chunk.line_numbers[i];
      const auto status = status_from_string(fields[c_status]);
      CONTACTNN_REQUIRE_AS(
          FormatError, status.has_value(),
          "'" << path.string() << "':" << line << ": column 'status': '" << fields[c_status]
              << "' is not a status (ok, outside, no_convergence, degenerate, invalid, no_segment)");
      if (chunk.no_segment[i] != 0 || *status == Status::kNoSegment) {
        ++out.skipped_no_segment;
        continue;
      }
      const bool has_label = *status == Status::kOk || *status == Status::kOutside;
      const auto number = [&](std::size_t c) {
        double value = 0.0;
        if (!has_label) return value;
        CONTACTNN_REQUIRE_AS(FormatError, io::parse_double(fields[c], value) && std::isfinite(value),
                             io::not_a_number_message(path, line, header[c], fields[c]));
        return value;
      };
      const double p0 = number(c0), p1 = number(c1), gap = number(c_gap);
      const geometry::Configuration& c = chunk.configs[i];
      append_raw(out.raw, c, kind);
      out.label_status.push_back(*status);
      out.label_gap.push_back(gap);
      out.size.push_back(geometry::max_node_distance(c.nodes));
      out.label_iterations.push_back(-1);
      labels.insert(labels.end(), {p0, p1});
    }
  }
  out.labels = Eigen::Map<const dataset::MatrixRM<double>>(labels.data(), out.rows(), 2);
  return out;
}

}  // namespace contactnn::eval
