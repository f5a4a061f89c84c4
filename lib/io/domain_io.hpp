// Reading and writing a TrainingDomain (and its DomainFilters) inside a contactnn HDF5 file.
#pragma once

#include <string>

#include "geometry/domain.hpp"
#include "io/hdf5_file.hpp"

namespace contactnn::io {

/// Writes the filters as attributes of `group` (one attribute per DomainFilters field, same names).
void write_filters(Hdf5File& file, const std::string& group, const geometry::DomainFilters& filters);
/// Reads them back; FormatError naming the file and attribute if one is missing.
[[nodiscard]] geometry::DomainFilters read_filters(const Hdf5File& file, const std::string& group);

/// Writes `group`/feature_min, `group`/feature_max (1-D, feature_count values), the surface attribute and
/// the filters.
void write_domain(Hdf5File& file, const std::string& group, const geometry::TrainingDomain& domain);
/// Reads them back; FormatError if a member is missing or has the wrong length for the surface.
[[nodiscard]] geometry::TrainingDomain read_domain(const Hdf5File& file, const std::string& group);

}  // namespace contactnn::io
