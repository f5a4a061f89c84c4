// The HDF5 dataset file of gen-configs (schema in README "Dataset schema").
#pragma once

#include <filesystem>

#include "dataset/labelled_set.hpp"

namespace contactnn::io {

/// Writes `set` to `path` atomically (temporary file, then rename). Layout (schema version
/// kDatasetSchemaVersion): root attributes kind = "contactnn-dataset", schema_version, surface, count,
/// feature_names, config; datasets /features (N x F double), /labels (N x 2 double), /gap (N double),
/// /iterations (N int32), /status (N uint8, Status values), /scale (N double); group /domain with the
/// generator's filters. Byte-identical output for identical input.
void write_dataset(const std::filesystem::path& path, const dataset::LabelledSet& set);

/// Reads and validates a dataset file. FormatError, naming the file and stating expected and actual, for a
/// file of another kind (a network), another schema version, or members of inconsistent shape.
[[nodiscard]] dataset::LabelledSet read_dataset(const std::filesystem::path& path);

}  // namespace contactnn::io
