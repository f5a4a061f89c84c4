// RAW.csv of SPEC 6: a user's configurations in world coordinates, and the labelled/predicted output
// that keeps every input row and column.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"
#include "io/csv.hpp"

namespace contactnn::io {

struct RawConfigurations {
  CsvTable table;                                ///< the file as text, for copying columns through
  std::vector<geometry::Configuration> configs;  ///< one per data row, in file order
};

/// Reads RAW.csv: columns ax..sz (and nax..ndz for Gregory) in any order, other columns allowed.
/// nan/inf parse (the row's status will be invalid). FormatError naming file, line and column for a
/// missing column or a field that is not a number; the CSV errors of read_csv.
[[nodiscard]] RawConfigurations read_raw_configurations(const std::filesystem::path& path, SurfaceKind kind);

/// Same, from CSV text in memory (`name` stands for the file in messages). Used by read_raw_configurations
/// and the fuzzer.
[[nodiscard]] RawConfigurations parse_raw_configurations(std::string_view text, const std::filesystem::path& name,
                                                         SurfaceKind kind);

/// Writes `input`'s header and rows followed by `extra_header` columns with `extra_rows` values, one per
/// input row, in input order, atomically. An input column with the same name as an extra column is
/// replaced by it (so an output can be fed back in); `replaced` receives those names.
void write_with_columns(const std::filesystem::path& path, const CsvTable& input,
                        const std::vector<std::string>& extra_header,
                        const std::vector<std::vector<std::string>>& extra_rows, std::vector<std::string>* replaced);

}  // namespace contactnn::io
