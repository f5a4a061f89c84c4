#include "io/raw_configurations.hpp"

#include <algorithm>
#include <limits>

#include "core/error.hpp"

namespace contactnn::io {

RawConfigurationReader::RawConfigurationReader(const std::filesystem::path& path, SurfaceKind kind,
                                               DataRows rows)
    : csv_(path, rows), kind_(kind) {
  locate_columns();
}

RawConfigurationReader::RawConfigurationReader(std::string_view text, const std::filesystem::path& name,
                                               SurfaceKind kind, DataRows rows)
    : csv_(text, name, rows), kind_(kind) {
  locate_columns();
}

void RawConfigurationReader::locate_columns() {
  for (std::size_t i = 0; i < kRawPointColumns.size(); ++i)
    point_columns_[i] = csv_.column(kRawPointColumns[i]);
  if (kind_ == SurfaceKind::kGregory) {
    for (std::size_t i = 0; i < kRawNormalColumns.size(); ++i)
      normal_columns_[i] = csv_.column(kRawNormalColumns[i]);
  }
}

bool RawConfigurationReader::next_chunk(RawChunk& chunk, std::size_t max_rows) {
  CONTACTNN_REQUIRE(max_rows >= 1, "chunk of " << max_rows << " rows");
  // Grown row by row (a short file costs a short chunk), and the records keep their storage from one full
  // chunk to the next.
  const bool gregory = kind_ == SurfaceKind::kGregory;
  std::size_t n = 0;
  for (; n < max_rows; ++n) {
    if (n == chunk.records.size()) chunk.records.emplace_back();
    if (n == chunk.line_numbers.size()) chunk.line_numbers.push_back(0);
    if (n == chunk.configs.size()) chunk.configs.emplace_back();
    if (n == chunk.no_segment.size()) chunk.no_segment.push_back(0);
    const CsvRecord& fields = chunk.records[n];
    if (!csv_.next(chunk.records[n], chunk.line_numbers[n])) break;
    const auto blank = [&](std::size_t column) {
      return fields[column].find_first_not_of(" \t") == std::string_view::npos;
    };
    bool all_blank = std::all_of(point_columns_.begin(), point_columns_.end(), blank);
    if (gregory) all_blank = all_blank && std::all_of(normal_columns_.begin(), normal_columns_.end(), blank);
    chunk.no_segment[n] = all_blank ? 1 : 0;
    if (all_blank) {
      constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
      geometry::Configuration& c = chunk.configs[n];
      for (int node = 0; node < 4; ++node) c.nodes[node] = c.normals[node] = geometry::Vec3::Constant(kNan);
      c.slave = geometry::Vec3::Constant(kNan);
      continue;
    }
    const auto number = [&](std::size_t column) {
      double value = 0.0;
      if (!parse_double(fields[column], value)) {
        throw FormatError(
            not_a_number_message(csv_.path(), chunk.line_numbers[n], csv_.header()[column], fields[column]));
      }
      return value;
    };
    geometry::Configuration& c = chunk.configs[n];
    for (int node = 0; node < 4; ++node) {
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<std::size_t>(3 * node + k);
        c.nodes[node][k] = number(point_columns_[i]);
        c.normals[node][k] = gregory ? number(normal_columns_[i]) : 0.0;
      }
    }
    for (int k = 0; k < 3; ++k) c.slave[k] = number(point_columns_[static_cast<std::size_t>(12 + k)]);
  }
  chunk.records.resize(n);
  chunk.line_numbers.resize(n);
  chunk.configs.resize(n);
  chunk.no_segment.resize(n);
  return n > 0;
}

RawConfigurations parse_raw_configurations(std::string_view text, const std::filesystem::path& name,
                                           SurfaceKind kind) {
  RawConfigurationReader reader(text, name, kind, DataRows::kMayBeNone);
  RawConfigurations raw;
  raw.table.path = name;
  raw.table.header = reader.header();
  RawChunk chunk;
  while (reader.next_chunk(chunk, kRawChunkRows)) {
    for (std::size_t i = 0; i < chunk.size(); ++i) {
      raw.table.rows.push_back(chunk.records[i].strings());
      raw.table.line_numbers.push_back(chunk.line_numbers[i]);
      raw.configs.push_back(chunk.configs[i]);
    }
  }
  return raw;
}

std::size_t map_raw_configurations(const std::filesystem::path& input, const std::filesystem::path& output,
                                   SurfaceKind kind, const std::vector<std::string>& extra_header,
                                   const ChunkComputation& compute, std::vector<std::string>* replaced,
                                   std::size_t chunk_rows) {
  RawConfigurationReader reader(input, kind, DataRows::kMayBeNone);
  const std::vector<std::string>& header = reader.header();
  std::vector<std::size_t> kept;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (std::find(extra_header.begin(), extra_header.end(), header[c]) == extra_header.end()) {
      kept.push_back(c);
    } else if (replaced != nullptr) {
      replaced->push_back(header[c]);
    }
  }
  CsvWriter writer(output);
  std::vector<std::string> fields;
  fields.reserve(kept.size() + extra_header.size());
  for (std::size_t c : kept) fields.push_back(header[c]);
  fields.insert(fields.end(), extra_header.begin(), extra_header.end());
  writer.write_row(fields);

  RawChunk chunk;
  std::vector<std::vector<std::string>> rows;
  std::size_t total = 0;
  while (reader.next_chunk(chunk, chunk_rows)) {
    rows.assign(chunk.size(), {});
    compute(chunk, rows);
    CONTACTNN_REQUIRE(rows.size() == chunk.size(),
                      "computed " << rows.size() << " rows for a chunk of " << chunk.size());
    for (std::size_t r = 0; r < chunk.size(); ++r) {
      CONTACTNN_REQUIRE(rows[r].size() == extra_header.size(),
                        "computed " << rows[r].size() << " fields for " << extra_header.size() << " columns");
      for (std::size_t c : kept) writer.field(chunk.records[r][c]);
      for (const std::string& f : rows[r]) writer.field(f);
      writer.end_row();
    }
    total += chunk.size();
  }
  writer.commit();
  return total;
}

}  // namespace contactnn::io
