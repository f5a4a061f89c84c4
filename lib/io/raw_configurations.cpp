#include "io/raw_configurations.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

/// The configurations of a table read from RAW.csv (columns located by name).
RawConfigurations from_table(CsvTable table, SurfaceKind kind) {
  RawConfigurations raw;
  raw.table = std::move(table);
  const CsvTable& t = raw.table;
  std::array<std::size_t, 15> point_columns{};
  for (std::size_t i = 0; i < kRawPointColumns.size(); ++i) point_columns[i] = t.column(kRawPointColumns[i]);
  std::array<std::size_t, 12> normal_columns{};
  const bool gregory = kind == SurfaceKind::kGregory;
  if (gregory) {
    for (std::size_t i = 0; i < kRawNormalColumns.size(); ++i) normal_columns[i] = t.column(kRawNormalColumns[i]);
  }
  raw.configs.resize(t.rows.size());
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    geometry::Configuration& c = raw.configs[r];
    for (int node = 0; node < 4; ++node) {
      for (int k = 0; k < 3; ++k) {
        c.nodes[node][k] = t.number(r, point_columns[static_cast<std::size_t>(3 * node + k)]);
        c.normals[node][k] = gregory ? t.number(r, normal_columns[static_cast<std::size_t>(3 * node + k)]) : 0.0;
      }
    }
    for (int k = 0; k < 3; ++k) c.slave[k] = t.number(r, point_columns[static_cast<std::size_t>(12 + k)]);
  }
  return raw;
}

}  // namespace

RawConfigurations read_raw_configurations(const std::filesystem::path& path, SurfaceKind kind) {
  return from_table(read_csv(path), kind);
}

RawConfigurations parse_raw_configurations(std::string_view text, const std::filesystem::path& name,
                                           SurfaceKind kind) {
  return from_table(parse_csv(text, name), kind);
}

void write_with_columns(const std::filesystem::path& path, const CsvTable& input,
                        const std::vector<std::string>& extra_header,
                        const std::vector<std::vector<std::string>>& extra_rows, std::vector<std::string>* replaced) {
  CONTACTNN_REQUIRE(extra_rows.size() == input.rows.size(),
                    "output has " << extra_rows.size() << " rows for " << input.rows.size() << " input rows");
  std::vector<std::size_t> kept;
  for (std::size_t c = 0; c < input.header.size(); ++c) {
    if (std::find(extra_header.begin(), extra_header.end(), input.header[c]) == extra_header.end()) {
      kept.push_back(c);
    } else if (replaced != nullptr) {
      replaced->push_back(input.header[c]);
    }
  }
  std::string text;
  std::vector<std::string> fields;
  fields.reserve(kept.size() + extra_header.size());
  for (std::size_t c : kept) fields.push_back(input.header[c]);
  fields.insert(fields.end(), extra_header.begin(), extra_header.end());
  append_csv_row(text, fields);
  for (std::size_t r = 0; r < input.rows.size(); ++r) {
    fields.clear();
    for (std::size_t c : kept) fields.push_back(input.rows[r][c]);
    fields.insert(fields.end(), extra_rows[r].begin(), extra_rows[r].end());
    append_csv_row(text, fields);
  }
  write_text_atomically(path, text);
}

}  // namespace contactnn::io
