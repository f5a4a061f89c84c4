// RAW.csv of SPEC 6: a user's configurations in world coordinates, read in chunks of rows, and the
// labelled/predicted output that keeps every input row and column, written as the chunks are done.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"
#include "io/csv.hpp"

namespace contactnn::io {

/// Rows per chunk of map_raw_configurations: about 25 MB of text and 20 MB of configurations in flight,
/// large enough that per-chunk overheads (an OpenMP region, a buffer flush) do not show.
inline constexpr std::size_t kRawChunkRows = 65536;

/// A run of consecutive RAW.csv rows: the fields as text (to copy through), the line each starts on, and
/// the configuration each holds.
struct RawChunk {
  std::vector<CsvRecord> records;
  std::vector<std::size_t> line_numbers;
  std::vector<geometry::Configuration> configs;
  /// 1 for a row whose coordinate (and normal) fields are all empty: a SPEC 7 pairs row of a slave node
  /// without a segment. Its configuration holds NaN; tools write it with empty values and status no_segment.
  std::vector<std::uint8_t> no_segment;
  [[nodiscard]] std::size_t size() const { return configs.size(); }
};

/// Reads RAW.csv chunk by chunk: columns ax..sz (and nax..ndz for Gregory) in any order, other columns
/// allowed. nan/inf parse (the row's status will be invalid). A row whose coordinate fields are all empty
/// (SPEC 7's no_segment rows: a pairs file is a valid RAW.csv) is marked in RawChunk::no_segment; some
/// empty and some not is a field that is not a number. FormatError naming file, line and column for
/// a missing column or a field that is not a number (reported when its chunk is read); the CSV errors of
/// CsvReader. Memory: one chunk, however long the file.
class RawConfigurationReader {
 public:
  RawConfigurationReader(const std::filesystem::path& path, SurfaceKind kind,
                         DataRows rows = DataRows::kRequired);
  /// From CSV text in memory (`name` stands for the file in messages); `text` must outlive the reader.
  RawConfigurationReader(std::string_view text, const std::filesystem::path& name, SurfaceKind kind,
                         DataRows rows = DataRows::kRequired);

  [[nodiscard]] const std::vector<std::string>& header() const { return csv_.header(); }
  [[nodiscard]] const std::filesystem::path& path() const { return csv_.path(); }

  /// Replaces `chunk`'s content by the next rows, at most `max_rows` (>= 1). False when no row is left.
  bool next_chunk(RawChunk& chunk, std::size_t max_rows);

 private:
  void locate_columns();

  CsvReader csv_;
  SurfaceKind kind_;
  std::array<std::size_t, 15> point_columns_{};
  std::array<std::size_t, 12> normal_columns_{};
};

/// The whole of a RAW.csv text in memory (the fuzzer's view): its table and one configuration per row; a
/// header alone is a table of no rows, as for map_raw_configurations.
struct RawConfigurations {
  CsvTable table;
  std::vector<geometry::Configuration> configs;
};
[[nodiscard]] RawConfigurations parse_raw_configurations(std::string_view text,
                                                         const std::filesystem::path& name, SurfaceKind kind);

/// The result columns a tool computes for one chunk: `rows[i]` holds the extra fields of the chunk's row i
/// (its configuration, line number for messages, and no_segment flag are the chunk's).
using ChunkComputation =
    std::function<void(const RawChunk& chunk, std::vector<std::vector<std::string>>& rows)>;

/// Streams `input` (RAW.csv) to `output`: chunk by chunk of `chunk_rows` rows, `compute` gives each row's
/// `extra_header` fields, and the output gets the input's header and rows followed by those columns, in
/// input order. An input column named like an extra column is replaced by it (so an output can be fed back
/// in); `replaced` (if not null) receives those names. A header without rows gives a header without rows
/// (SPEC 7: the pairs file of a pair without slave nodes is valid input). The output is atomic
/// (AtomicOutput): an error at any row, however late, leaves no output and no temporary. Returns the number
/// of rows.
std::size_t map_raw_configurations(const std::filesystem::path& input, const std::filesystem::path& output,
                                   SurfaceKind kind, const std::vector<std::string>& extra_header,
                                   const ChunkComputation& compute, std::vector<std::string>* replaced,
                                   std::size_t chunk_rows = kRawChunkRows);

}  // namespace contactnn::io
