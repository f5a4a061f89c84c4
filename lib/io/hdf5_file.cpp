#include "io/hdf5_file.hpp"

#include <hdf5.h>

#include <limits>
#include <new>
#include <sstream>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

// HDF5 prints its own error stack to stderr by default; contactnn reports errors itself, once.
void silence_hdf5() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

template <class T>
hid_t native_type();
template <>
hid_t native_type<float>() { return H5T_NATIVE_FLOAT; }
template <>
hid_t native_type<double>() { return H5T_NATIVE_DOUBLE; }
template <>
hid_t native_type<std::int32_t>() { return H5T_NATIVE_INT32; }
template <>
hid_t native_type<std::uint8_t>() { return H5T_NATIVE_UINT8; }
template <>
hid_t native_type<std::int64_t>() { return H5T_NATIVE_INT64; }

/// Closes an HDF5 handle with the matching close function when it leaves scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), closer_(closer) {}
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
  [[nodiscard]] hid_t get() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*closer_)(hid_t);
};

std::string where(const std::filesystem::path& path, const std::string& name) {
  return "'" + path.string() + "', '" + name + "'";
}

/// True when every group on the way to `name` and `name` itself exist (H5Lexists needs each step).
bool link_exists(hid_t file, const std::string& name) {
  if (name == "/" || name.empty()) return true;
  std::string partial;
  std::istringstream parts(name);
  std::string part;
  while (std::getline(parts, part, '/')) {
    if (part.empty()) continue;
    partial += "/" + part;
    if (H5Lexists(file, partial.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

Handle create_dataset(hid_t file, const std::filesystem::path& path, const std::string& name, hid_t type,
                      int rank, const hsize_t* dims) {
  Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  Handle link_props(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(link_props.get(), 1);
  // No modification times in the file: the same content gives the same bytes (reproducible datasets).
  Handle create_props(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(create_props.get(), 0);
  Handle dataset(
      H5Dcreate2(file, name.c_str(), type, space.get(), link_props.get(), create_props.get(), H5P_DEFAULT),
      H5Dclose);
  CONTACTNN_REQUIRE_AS(IoError, dataset.valid(), "cannot create dataset " << where(path, name));
  return Handle(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
}

Handle open_dataset(hid_t file, const std::filesystem::path& path, const std::string& name) {
  CONTACTNN_REQUIRE_AS(FormatError, link_exists(file, name),
                       "dataset " << where(path, name) << " does not exist");
  Handle dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
  CONTACTNN_REQUIRE_AS(FormatError, dataset.valid(), "cannot open dataset " << where(path, name));
  return dataset;
}

std::vector<hsize_t> dataset_dims(hid_t dataset) {
  Handle space(H5Dget_space(dataset), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

/// A corrupt object header can claim any dimensions. Before anything is allocated, the element count must
/// fit in the storage the file holds for the dataset (contiguous layout, the one Hdf5File writes; other
/// layouts cannot be checked this way, and a failed allocation is still reported as FormatError).
void require_stored(hid_t dataset, const std::filesystem::path& path, const std::string& name,
                    const std::vector<hsize_t>& dims) {
  hsize_t count = 1;
  bool overflow = false;
  for (const hsize_t d : dims) {
    if (d != 0 && count > std::numeric_limits<hsize_t>::max() / d) overflow = true;
    count *= d;
  }
  const Handle type(H5Dget_type(dataset), H5Tclose);
  const Handle create_props(H5Dget_create_plist(dataset), H5Pclose);
  const std::size_t element = type.valid() ? H5Tget_size(type.get()) : 0;
  if (!create_props.valid() || H5Pget_layout(create_props.get()) != H5D_CONTIGUOUS) return;
  const hsize_t stored = H5Dget_storage_size(dataset);
  std::ostringstream shape;
  for (std::size_t i = 0; i < dims.size(); ++i) shape << (i > 0 ? "x" : "") << dims[i];
  CONTACTNN_REQUIRE_AS(FormatError, !overflow && element > 0 && count <= stored / element,
                       "dataset " << where(path, name) << " claims " << shape.str() << " elements of " << element
                                  << " bytes but the file stores " << stored
                                  << " bytes for it (the file is truncated or corrupt)");
}

Handle open_attribute(hid_t file, const std::filesystem::path& path, const std::string& object,
                      const std::string& name) {
  const std::string label = object + "@" + name;
  CONTACTNN_REQUIRE_AS(FormatError, link_exists(file, object) && H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0,
                       "attribute " << where(path, label) << " does not exist");
  Handle attribute(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  CONTACTNN_REQUIRE_AS(FormatError, attribute.valid(), "cannot open attribute " << where(path, label));
  return attribute;
}

void write_scalar_attribute(hid_t file, const std::filesystem::path& path, const std::string& object,
                            const std::string& name, hid_t type, const void* value) {
  if (H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
    H5Adelete_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT);
  }
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attribute(H5Acreate_by_name(file, object.c_str(), name.c_str(), type, space.get(), H5P_DEFAULT,
                                     H5P_DEFAULT, H5P_DEFAULT),
                   H5Aclose);
  CONTACTNN_REQUIRE_AS(IoError, attribute.valid() && H5Awrite(attribute.get(), type, value) >= 0,
                       "cannot write attribute " << where(path, object + "@" + name));
}

}  // namespace

Hdf5File::Hdf5File(const std::filesystem::path& path, Mode mode) : path_(path) {
  silence_hdf5();
  if (mode == Mode::kCreate) {
    file_id_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CONTACTNN_REQUIRE_AS(IoError, file_id_ >= 0, "cannot create HDF5 file '" << path.string() << "'");
    return;
  }
  std::error_code ec;
  CONTACTNN_REQUIRE_AS(IoError, std::filesystem::is_regular_file(path, ec),
                       "cannot open '" << path.string() << "': no such file");
  CONTACTNN_REQUIRE_AS(FormatError, H5Fis_hdf5(path.c_str()) > 0,
                       "'" << path.string() << "' is not an HDF5 file, or it is truncated or corrupt");
  file_id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  CONTACTNN_REQUIRE_AS(FormatError, file_id_ >= 0,
                       "cannot open '" << path.string() << "' as HDF5: the file is truncated or corrupt");
}

Hdf5File::~Hdf5File() {
  if (file_id_ >= 0) H5Fclose(file_id_);
}

void Hdf5File::close() {
  if (file_id_ < 0) return;
  const herr_t flushed = H5Fflush(file_id_, H5F_SCOPE_GLOBAL);
  const herr_t closed = H5Fclose(file_id_);
  file_id_ = -1;
  CONTACTNN_REQUIRE_AS(IoError, flushed >= 0 && closed >= 0, "cannot flush and close '" << path_.string() << "'");
}

template <class T>
void Hdf5File::write_matrix(const std::string& name, const MatrixRM<T>& matrix) {
  const hsize_t dims[2] = {static_cast<hsize_t>(matrix.rows()), static_cast<hsize_t>(matrix.cols())};
  Handle dataset = create_dataset(file_id_, path_, name, native_type<T>(), 2, dims);
  CONTACTNN_REQUIRE_AS(IoError,
                       matrix.size() == 0 ||
                           H5Dwrite(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, matrix.data()) >= 0,
                       "cannot write dataset " << where(path_, name));
}

template <class T>
void Hdf5File::write_vector(const std::string& name, const std::vector<T>& values) {
  const hsize_t dims[1] = {static_cast<hsize_t>(values.size())};
  Handle dataset = create_dataset(file_id_, path_, name, native_type<T>(), 1, dims);
  CONTACTNN_REQUIRE_AS(IoError,
                       values.empty() ||
                           H5Dwrite(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0,
                       "cannot write dataset " << where(path_, name));
}

template <class T>
MatrixRM<T> Hdf5File::read_matrix(const std::string& name) const {
  Handle dataset = open_dataset(file_id_, path_, name);
  const auto dims = dataset_dims(dataset.get());
  CONTACTNN_REQUIRE_AS(FormatError, dims.size() == 2,
                       "dataset " << where(path_, name) << " has rank " << dims.size() << ", expected a 2-D matrix");
  require_stored(dataset.get(), path_, name, dims);
  MatrixRM<T> matrix;
  try {
    matrix.resize(static_cast<Eigen::Index>(dims[0]), static_cast<Eigen::Index>(dims[1]));
  } catch (const std::bad_alloc&) {
    throw FormatError("dataset " + where(path_, name) + " claims " + std::to_string(dims[0]) + "x" +
                      std::to_string(dims[1]) + " elements: more than memory holds (corrupt?)");
  }
  CONTACTNN_REQUIRE_AS(FormatError,
                       matrix.size() == 0 ||
                           H5Dread(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, matrix.data()) >= 0,
                       "cannot read dataset " << where(path_, name) << " (corrupt, or not numeric)");
  return matrix;
}

template <class T>
std::vector<T> Hdf5File::read_vector(const std::string& name) const {
  Handle dataset = open_dataset(file_id_, path_, name);
  const auto dims = dataset_dims(dataset.get());
  CONTACTNN_REQUIRE_AS(FormatError, dims.size() == 1,
                       "dataset " << where(path_, name) << " has rank " << dims.size() << ", expected a 1-D vector");
  require_stored(dataset.get(), path_, name, dims);
  std::vector<T> values;
  try {
    values.resize(dims[0]);
  } catch (const std::bad_alloc&) {
    throw FormatError("dataset " + where(path_, name) + " claims " + std::to_string(dims[0]) +
                      " elements: more than memory holds (corrupt?)");
  }
  CONTACTNN_REQUIRE_AS(FormatError,
                       values.empty() ||
                           H5Dread(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0,
                       "cannot read dataset " << where(path_, name) << " (corrupt, or not numeric)");
  return values;
}

std::vector<std::int64_t> Hdf5File::shape(const std::string& name) const {
  Handle dataset = open_dataset(file_id_, path_, name);
  const auto dims = dataset_dims(dataset.get());
  return {dims.begin(), dims.end()};
}

bool Hdf5File::has_dataset(const std::string& name) const {
  if (!link_exists(file_id_, name)) return false;
  const Handle dataset(H5Dopen2(file_id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  return dataset.valid();
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  std::string padded = value;
  padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
  write_scalar_attribute(file_id_, path_, object, name, type.get(), padded.data());
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, double value) {
  write_scalar_attribute(file_id_, path_, object, name, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, std::int64_t value) {
  write_scalar_attribute(file_id_, path_, object, name, H5T_NATIVE_INT64, &value);
}

bool Hdf5File::has_attribute(const std::string& object, const std::string& name) const {
  return link_exists(file_id_, object) && H5Aexists_by_name(file_id_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string Hdf5File::read_string_attribute(const std::string& object, const std::string& name) const {
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  CONTACTNN_REQUIRE_AS(FormatError, H5Tget_class(type.get()) == H5T_STRING && H5Tis_variable_str(type.get()) == 0,
                       "attribute " << where(path_, object + "@" + name) << " is not a fixed-length string");
  // An attribute cannot be longer than the file: a larger size is a corrupt header, not an allocation.
  hsize_t file_size = 0;
  H5Fget_filesize(file_id_, &file_size);
  const std::size_t size = H5Tget_size(type.get());
  CONTACTNN_REQUIRE_AS(FormatError, size <= file_size,
                       "attribute " << where(path_, object + "@" + name) << " claims " << size << " bytes in a file of "
                                    << file_size << " (corrupt)");
  std::string value(size, '\0');
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), type.get(), value.data()) >= 0,
                       "cannot read attribute " << where(path_, object + "@" + name));
  value.resize(value.find_last_not_of('\0') == std::string::npos ? 0 : value.find_last_not_of('\0') + 1);
  return value;
}

double Hdf5File::read_double_attribute(const std::string& object, const std::string& name) const {
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  CONTACTNN_REQUIRE_AS(FormatError, H5Tget_class(type.get()) == H5T_FLOAT || H5Tget_class(type.get()) == H5T_INTEGER,
                       "attribute " << where(path_, object + "@" + name) << " is not a number");
  double value = 0.0;
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value) >= 0,
                       "cannot read attribute " << where(path_, object + "@" + name));
  return value;
}

std::int64_t Hdf5File::read_int_attribute(const std::string& object, const std::string& name) const {
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  CONTACTNN_REQUIRE_AS(FormatError, H5Tget_class(type.get()) == H5T_INTEGER,
                       "attribute " << where(path_, object + "@" + name) << " is not an integer");
  std::int64_t value = 0;
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), H5T_NATIVE_INT64, &value) >= 0,
                       "cannot read attribute " << where(path_, object + "@" + name));
  return value;
}

void require_file_kind(const Hdf5File& file, std::string_view expected_kind, std::int64_t expected_version) {
  const std::string path = file.path().string();
  CONTACTNN_REQUIRE_AS(FormatError, file.has_attribute("/", "kind"),
                       "'" << path << "' is not a contactnn file: root attribute 'kind' is missing (expected '"
                           << expected_kind << "')");
  const std::string kind = file.read_string_attribute("/", "kind");
  CONTACTNN_REQUIRE_AS(FormatError, kind == expected_kind,
                       "'" << path << "' is a " << kind << " file, expected a " << expected_kind << " file");
  CONTACTNN_REQUIRE_AS(FormatError, file.has_attribute("/", "schema_version"),
                       "'" << path << "': root attribute 'schema_version' is missing (expected " << expected_version << ")");
  const std::int64_t version = file.read_int_attribute("/", "schema_version");
  CONTACTNN_REQUIRE_AS(FormatError, version == expected_version,
                       "'" << path << "' has " << expected_kind << " schema version " << version << ", expected "
                           << expected_version);
}

SurfaceKind read_surface_attribute(const Hdf5File& file, const std::string& object, const std::string& name) {
  const std::string value = file.read_string_attribute(object, name);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    if (value == to_string(kind)) return kind;
  }
  throw FormatError("attribute " + where(file.path(), object + "@" + name) + " is '" + value +
                    "', expected 'bilinear' or 'gregory'");
}

#define CONTACTNN_INSTANTIATE(T)                                                      \
  template void Hdf5File::write_matrix<T>(const std::string&, const MatrixRM<T>&);    \
  template void Hdf5File::write_vector<T>(const std::string&, const std::vector<T>&); \
  template MatrixRM<T> Hdf5File::read_matrix<T>(const std::string&) const;            \
  template std::vector<T> Hdf5File::read_vector<T>(const std::string&) const;
CONTACTNN_INSTANTIATE(float)
CONTACTNN_INSTANTIATE(double)
CONTACTNN_INSTANTIATE(std::int32_t)
CONTACTNN_INSTANTIATE(std::uint8_t)
CONTACTNN_INSTANTIATE(std::int64_t)
#undef CONTACTNN_INSTANTIATE

}  // namespace contactnn::io
