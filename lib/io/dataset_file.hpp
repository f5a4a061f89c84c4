// The HDF5 dataset file of gen-configs (schema: docs/files.md, "Dataset").
#pragma once

#include <filesystem>
#include <memory>

#include "dataset/labelled_set.hpp"
#include "io/atomic_output.hpp"

namespace contactnn::io {

/// Writes `set` to `path` atomically (temporary file, then rename). Layout (schema version
/// kDatasetSchemaVersion): root attributes kind = "contactnn-dataset", schema_version, surface, count,
/// feature_names, config; datasets /features (N x F double), /labels (N x 2 double), /gap (N double),
/// /iterations (N int32), /status (N uint8, Status values), /scale (N double); group /domain with the
/// generator's filters. Byte-identical output for identical input.
void write_dataset(const std::filesystem::path& path, const dataset::LabelledSet& set);

/// The same, leaving the commit to the caller (to commit the dataset and its effective config together,
/// io::commit_together). Nothing appears under `path` unless the returned output is committed.
[[nodiscard]] std::unique_ptr<AtomicOutput> write_dataset_uncommitted(const std::filesystem::path& path,
                                                                      const dataset::LabelledSet& set);

/// Reads and validates a dataset file. FormatError, naming the file and stating expected and actual, for a
/// file of another kind (a network), another schema version, or members of inconsistent shape or of a type
/// that is not the schema's. Files written by other tools (h5py) in this schema read as long as each member
/// is of the schema's kind of type (Hdf5File: float32 features, int64 status and iterations, chunked and
/// gzip-compressed datasets, variable-length string attributes); status codes and iteration counts are
/// range-checked.
[[nodiscard]] dataset::LabelledSet read_dataset(const std::filesystem::path& path);

}  // namespace contactnn::io
