// A thin RAII layer over HDF5's C API: the only place HDF5 appears in contactnn.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/conventions.hpp"

namespace contactnn::io {

template <class T>
using MatrixRM = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// One open HDF5 file. Datasets and attributes are addressed by path ("layers/0/weights"); groups on
/// the way are created on demand when writing. Element types: float, double, std::int32_t,
/// std::uint8_t, std::int64_t. Matrices are stored row-major as 2-D datasets (rows x cols), vectors as
/// 1-D datasets.
///
/// Reading accepts what other HDF5 writers (h5py) produce for the same schema: datasets of any floating-point
/// width where reals are expected and of any integer width and signedness where integers are (values are
/// range-checked against the type asked for), contiguous, chunked or compressed (gzip, shuffle) layouts,
/// fixed- or variable-length (ASCII or UTF-8) string attributes, numpy booleans (an enum) as integer
/// attributes, and attributes stored as one-element arrays. Integers where reals are expected, or the
/// reverse, and anything else ambiguous are FormatError naming both sides.
///
/// Errors: a missing file, or one that cannot be created or written (a full disk), is IoError; a file that
/// is not HDF5 (or is truncated or corrupt), a missing dataset or attribute, or a dataset of another rank or
/// type is FormatError. Every message names the file and the dataset or attribute.
///
/// The process never terminates HDF5 after a close has failed (see hdf5_file.cpp): a failed write ends in
/// IoError and a normal exit, never in a crash in HDF5's exit handling.
class Hdf5File {
 public:
  enum class Mode { kRead, kCreate };  ///< kCreate truncates an existing file

  /// `shown_as`: the name used in write errors (the final name of an output written to a temporary).
  Hdf5File(const std::filesystem::path& path, Mode mode, std::filesystem::path shown_as = {});
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  template <class T>
  void write_matrix(const std::string& name, const MatrixRM<T>& matrix);
  template <class T>
  void write_vector(const std::string& name, const std::vector<T>& values);
  template <class T>
  [[nodiscard]] MatrixRM<T> read_matrix(const std::string& name) const;
  template <class T>
  [[nodiscard]] std::vector<T> read_vector(const std::string& name) const;

  /// Dimensions of a dataset (FormatError if it does not exist).
  [[nodiscard]] std::vector<std::int64_t> shape(const std::string& name) const;
  [[nodiscard]] bool has_dataset(const std::string& name) const;

  /// Attributes on an object: `object` is "/" for the file root, or a dataset/group path.
  void write_attribute(const std::string& object, const std::string& name, const std::string& value);
  void write_attribute(const std::string& object, const std::string& name, double value);
  void write_attribute(const std::string& object, const std::string& name, std::int64_t value);
  [[nodiscard]] bool has_attribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] std::string read_string_attribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] double read_double_attribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] std::int64_t read_int_attribute(const std::string& object, const std::string& name) const;

  /// Flushes and closes now (also done by the destructor, which cannot report errors).
  void close();

 private:
  std::filesystem::path path_;
  std::string shown_;
  std::int64_t file_id_ = -1;  // hid_t
};

/// Root attribute checks shared by every contactnn file kind: `kind` must equal `expected_kind`
/// (a network is not a dataset) and `schema_version` must equal `expected_version`. FormatError with
/// both sides of the mismatch and the file name otherwise.
void require_file_kind(const Hdf5File& file, std::string_view expected_kind, std::int64_t expected_version);

/// String attribute `name` of `object` read as a surface kind ("bilinear" or "gregory"). FormatError naming
/// the file, the attribute and the value found otherwise (a corrupt or foreign file, not a usage error).
[[nodiscard]] SurfaceKind read_surface_attribute(const Hdf5File& file, const std::string& object,
                                                 const std::string& name);

}  // namespace contactnn::io
