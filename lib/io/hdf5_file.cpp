#include "io/hdf5_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <sstream>
#include <type_traits>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

// Why HDF5's own exit handler is switched off. When H5Fclose fails while flushing (a full disk), HDF5 1.10
// has already torn down part of the file object but leaves its id registered; the H5_term_library that HDF5
// registers with atexit() then closes that id again and dereferences the freed state: the process that
// reported "disk full" correctly would end with a segmentation fault. So the library is initialised with
// H5dont_atexit() and terminated by our own exit handler, which skips the termination once a close has
// failed: nothing is left to flush then (the failed file is a temporary that is being deleted, files read
// need no flush), and the system reclaims the rest at exit.
std::atomic<bool> g_close_failed{false};

void initialise_hdf5() {
  static const bool initialised = [] {
    H5dont_atexit();  // before the first call that initialises the library
    H5open();
    // HDF5 prints its own error stack to stderr by default; contactnn reports errors itself, once.
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    std::atexit([] {
      if (!g_close_failed.load()) H5close();
    });
    return true;
  }();
  (void)initialised;
}

/// Closes a file; on failure records that the library must not be terminated (see above).
herr_t close_file(hid_t file) {
  const herr_t result = H5Fclose(file);
  if (result < 0) g_close_failed.store(true);
  return result;
}

/// The system's reason for the last failed write, when it names one a user can act on.
std::string system_reason(int error) {
  switch (error) {
    case ENOSPC:
    case EDQUOT:
    case EFBIG:
    case EIO:
    case EROFS:
    case EACCES: return std::string(": ") + std::strerror(error);
    default: return "";
  }
}

template <class T>
hid_t native_type();
template <>
hid_t native_type<float>() {
  return H5T_NATIVE_FLOAT;
}
template <>
hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
hid_t native_type<std::int32_t>() {
  return H5T_NATIVE_INT32;
}
template <>
hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}
template <>
hid_t native_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}

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

Handle create_dataset(hid_t file, const std::string& shown, const std::string& name, hid_t type, int rank,
                      const hsize_t* dims) {
  Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  Handle link_props(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(link_props.get(), 1);
  // No modification times in the file: the same content gives the same bytes (reproducible datasets).
  Handle create_props(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(create_props.get(), 0);
  errno = 0;
  Handle dataset(
      H5Dcreate2(file, name.c_str(), type, space.get(), link_props.get(), create_props.get(), H5P_DEFAULT),
      H5Dclose);
  CONTACTNN_REQUIRE_AS(IoError, dataset.valid(),
                       "cannot create dataset '" << shown << "', '" << name << "'" << system_reason(errno));
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
/// fit in the storage the file holds for the dataset (contiguous layout, the one Hdf5File writes; chunked
/// and compressed layouts store less than they hold, so they cannot be checked this way, and a failed
/// allocation is still reported as FormatError). A chunked dataset's filters must be available here.
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
  if (!create_props.valid()) return;
  for (int f = 0; f < H5Pget_nfilters(create_props.get()); ++f) {
    unsigned flags = 0;
    std::size_t values = 0;
    char filter_name[64] = {};
    const H5Z_filter_t filter = H5Pget_filter2(create_props.get(), static_cast<unsigned>(f), &flags, &values,
                                               nullptr, sizeof filter_name, filter_name, nullptr);
    CONTACTNN_REQUIRE_AS(
        FormatError, filter >= 0 && H5Zfilter_avail(filter) > 0,
        "dataset " << where(path, name) << " is stored with HDF5 filter " << filter << " ('" << filter_name
                   << "'), which this HDF5 library does not have (gzip, shuffle and fletcher32 "
                      "are built in: save it with compression='gzip')");
  }
  if (H5Pget_layout(create_props.get()) != H5D_CONTIGUOUS) return;
  const hsize_t stored = H5Dget_storage_size(dataset);
  std::ostringstream shape;
  for (std::size_t i = 0; i < dims.size(); ++i) shape << (i > 0 ? "x" : "") << dims[i];
  CONTACTNN_REQUIRE_AS(FormatError, !overflow && element > 0 && count <= stored / element,
                       "dataset " << where(path, name) << " claims " << shape.str() << " elements of "
                                  << element << " bytes but the file stores " << stored
                                  << " bytes for it (the file is truncated or corrupt)");
}

/// The dataset `name` of `file` for reading as a whole: it must have `rank` dimensions (`expected` says so in
/// words: "a 2-D matrix") and be stored whole (require_stored); `dims` receives its dimensions.
Handle open_stored(hid_t file, const std::filesystem::path& path, const std::string& name, std::size_t rank,
                   const char* expected, std::vector<hsize_t>& dims) {
  Handle dataset = open_dataset(file, path, name);
  dims = dataset_dims(dataset.get());
  CONTACTNN_REQUIRE_AS(
      FormatError, dims.size() == rank,
      "dataset " << where(path, name) << " has rank " << dims.size() << ", expected " << expected);
  require_stored(dataset.get(), path, name, dims);
  return dataset;
}

/// resize(), with FormatError for std::bad_alloc: dimensions (`claimed`, "3x4") that memory cannot hold are a
/// corrupt file's.
template <class Resize>
void resize_to_claim(const std::filesystem::path& path, const std::string& name, const std::string& claimed,
                     const Resize& resize) {
  try {
    resize();
  } catch (const std::bad_alloc&) {
    throw FormatError("dataset " + where(path, name) + " claims " + claimed +
                      " elements: more than memory holds (corrupt?)");
  }
}

/// What a stored type is, in words, for messages: "float32", "uint16", "variable-length string".
std::string type_text(hid_t type) {
  const H5T_class_t type_class = H5Tget_class(type);
  const std::size_t bits = 8 * H5Tget_size(type);
  switch (type_class) {
    case H5T_FLOAT: return "float" + std::to_string(bits);
    case H5T_INTEGER: return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + std::to_string(bits);
    case H5T_STRING: return H5Tis_variable_str(type) > 0 ? "variable-length string" : "fixed-length string";
    case H5T_ENUM: return "enum";
    case H5T_COMPOUND: return "compound";
    case H5T_ARRAY: return "array";
    case H5T_VLEN: return "variable-length sequence";
    default: return "another HDF5 type";
  }
}

Handle open_attribute(hid_t file, const std::filesystem::path& path, const std::string& object,
                      const std::string& name) {
  const std::string label = object + "@" + name;
  CONTACTNN_REQUIRE_AS(
      FormatError,
      link_exists(file, object) && H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0,
      "attribute " << where(path, label) << " does not exist");
  Handle attribute(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  CONTACTNN_REQUIRE_AS(FormatError, attribute.valid(), "cannot open attribute " << where(path, label));
  // One value: a scalar, or (as some writers store it) an array of one element. Reading a longer array into
  // one value would write past it.
  const Handle space(H5Aget_space(attribute.get()), H5Sclose);
  const hssize_t points = space.valid() ? H5Sget_simple_extent_npoints(space.get()) : -1;
  CONTACTNN_REQUIRE_AS(FormatError, points == 1,
                       "attribute " << where(path, label) << " holds " << points << " values, expected one");
  return attribute;
}

void write_scalar_attribute(hid_t file, const std::string& shown, const std::string& object,
                            const std::string& name, hid_t type, const void* value) {
  if (H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
    H5Adelete_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT);
  }
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  errno = 0;
  Handle attribute(H5Acreate_by_name(file, object.c_str(), name.c_str(), type, space.get(), H5P_DEFAULT,
                                     H5P_DEFAULT, H5P_DEFAULT),
                   H5Aclose);
  CONTACTNN_REQUIRE_AS(
      IoError, attribute.valid() && H5Awrite(attribute.get(), type, value) >= 0,
      "cannot write attribute '" << shown << "', '" << object << "@" << name << "'" << system_reason(errno));
}

/// Reads a numeric dataset of any integer width and signedness as int64 (every such value fits, except
/// uint64 values above INT64_MAX, which are clamped and then fail the caller's range check), or of any
/// floating-point width as double. Integers where reals are expected, and the reverse, are an error
/// naming both types: a guess would hide a file that is not what it claims.
template <class T>
void read_numbers(hid_t dataset, const std::filesystem::path& path, const std::string& name,
                  std::size_t count, T* out) {
  const Handle type(H5Dget_type(dataset), H5Tclose);
  const H5T_class_t stored = H5Tget_class(type.get());
  const std::string read_error = "cannot read dataset " + where(path, name) + " (truncated or corrupt)";
  if constexpr (std::is_floating_point_v<T>) {
    CONTACTNN_REQUIRE_AS(FormatError, stored == H5T_FLOAT,
                         "dataset " << where(path, name) << " is " << type_text(type.get())
                                    << ", expected floating point (float32 or float64)");
    CONTACTNN_REQUIRE_AS(
        FormatError,
        count == 0 || H5Dread(dataset, native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0,
        read_error);
  } else {
    CONTACTNN_REQUIRE_AS(FormatError, stored == H5T_INTEGER,
                         "dataset " << where(path, name) << " is " << type_text(type.get())
                                    << ", expected integers (any width)");
    std::vector<std::int64_t> wide;
    try {
      wide.resize(count);
    } catch (const std::bad_alloc&) {
      throw FormatError("dataset " + where(path, name) + " claims " + std::to_string(count) +
                        " elements: more than memory holds (corrupt?)");
    }
    CONTACTNN_REQUIRE_AS(
        FormatError,
        count == 0 || H5Dread(dataset, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, wide.data()) >= 0,
        read_error);
    const bool unsigned_64 = H5Tget_sign(type.get()) == H5T_SGN_NONE && H5Tget_size(type.get()) >= 8;
    for (std::size_t i = 0; i < count; ++i) {
      const std::int64_t v = wide[i];
      const bool fits = !(unsigned_64 && v == std::numeric_limits<std::int64_t>::max()) &&
                        v >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
                        v <= static_cast<std::int64_t>(std::numeric_limits<T>::max());
      CONTACTNN_REQUIRE_AS(FormatError, fits,
                           "dataset " << where(path, name) << " element " << i << " is "
                                      << (unsigned_64 && v == std::numeric_limits<std::int64_t>::max()
                                              ? std::string("at least 2^63")
                                              : std::to_string(v))
                                      << ", outside the range of " << (std::is_signed_v<T> ? "int" : "uint")
                                      << 8 * sizeof(T) << " the schema gives it");
      out[i] = static_cast<T>(v);
    }
  }
}

/// The integer of `sizeof(Signed)` bytes at `raw` in native order, signed or not.
template <class Signed, class Unsigned>
std::int64_t native_integer(const unsigned char* raw, bool is_signed) {
  static_assert(sizeof(Signed) == sizeof(Unsigned) && sizeof(Signed) < 8);
  Signed s;
  Unsigned u;
  std::memcpy(&s, raw, sizeof s);
  std::memcpy(&u, raw, sizeof u);
  return is_signed ? static_cast<std::int64_t>(s) : static_cast<std::int64_t>(u);
}

}  // namespace

Hdf5File::Hdf5File(const std::filesystem::path& path, Mode mode, std::filesystem::path shown_as)
    : path_(path), shown_(shown_as.empty() ? path.string() : shown_as.string()) {
  initialise_hdf5();
  if (mode == Mode::kCreate) {
    errno = 0;
    file_id_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CONTACTNN_REQUIRE_AS(IoError, file_id_ >= 0,
                         "cannot create HDF5 file '" << shown_ << "'" << system_reason(errno));
    return;
  }
  std::error_code ec;
  CONTACTNN_REQUIRE_AS(IoError, std::filesystem::exists(path, ec),
                       "cannot open '" << path.string() << "': no such file");
  CONTACTNN_REQUIRE_AS(IoError, !std::filesystem::is_directory(path, ec),
                       "cannot open '" << path.string() << "': it is a directory");
  // HDF5 reads by seeking: a FIFO or a device would block or mislead it.
  CONTACTNN_REQUIRE_AS(IoError, std::filesystem::is_regular_file(path, ec),
                       "cannot open '" << path.string()
                                       << "' as HDF5: it is not a regular file (HDF5 needs a "
                                          "seekable file)");
  CONTACTNN_REQUIRE_AS(FormatError, H5Fis_hdf5(path.c_str()) > 0,
                       "'" << path.string() << "' is not an HDF5 file, or it is truncated or corrupt");
  file_id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  CONTACTNN_REQUIRE_AS(FormatError, file_id_ >= 0,
                       "cannot open '" << path.string() << "' as HDF5: the file is truncated or corrupt");
}

Hdf5File::~Hdf5File() {
  if (file_id_ >= 0) close_file(file_id_);
}

void Hdf5File::close() {
  if (file_id_ < 0) return;
  errno = 0;
  const herr_t flushed = H5Fflush(file_id_, H5F_SCOPE_GLOBAL);
  const int flush_errno = errno;
  const herr_t closed = close_file(file_id_);
  const int close_errno = errno;
  file_id_ = -1;
  CONTACTNN_REQUIRE_AS(IoError, flushed >= 0 && closed >= 0,
                       "cannot flush and close '"
                           << shown_ << "'" << system_reason(flush_errno != 0 ? flush_errno : close_errno));
}

template <class T>
void Hdf5File::write_matrix(const std::string& name, const MatrixRM<T>& matrix) {
  const hsize_t dims[2] = {static_cast<hsize_t>(matrix.rows()), static_cast<hsize_t>(matrix.cols())};
  Handle dataset = create_dataset(file_id_, shown_, name, native_type<T>(), 2, dims);
  errno = 0;
  CONTACTNN_REQUIRE_AS(IoError,
                       matrix.size() == 0 || H5Dwrite(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL,
                                                      H5P_DEFAULT, matrix.data()) >= 0,
                       "cannot write dataset '" << shown_ << "', '" << name << "'" << system_reason(errno));
}

template <class T>
void Hdf5File::write_vector(const std::string& name, const std::vector<T>& values) {
  const hsize_t dims[1] = {static_cast<hsize_t>(values.size())};
  Handle dataset = create_dataset(file_id_, shown_, name, native_type<T>(), 1, dims);
  errno = 0;
  CONTACTNN_REQUIRE_AS(IoError,
                       values.empty() || H5Dwrite(dataset.get(), native_type<T>(), H5S_ALL, H5S_ALL,
                                                  H5P_DEFAULT, values.data()) >= 0,
                       "cannot write dataset '" << shown_ << "', '" << name << "'" << system_reason(errno));
}

template <class T>
MatrixRM<T> Hdf5File::read_matrix(const std::string& name) const {
  std::vector<hsize_t> dims;
  const Handle dataset = open_stored(file_id_, path_, name, 2, "a 2-D matrix", dims);
  MatrixRM<T> matrix;
  resize_to_claim(path_, name, std::to_string(dims[0]) + "x" + std::to_string(dims[1]), [&] {
    matrix.resize(static_cast<Eigen::Index>(dims[0]), static_cast<Eigen::Index>(dims[1]));
  });
  read_numbers(dataset.get(), path_, name, static_cast<std::size_t>(matrix.size()), matrix.data());
  return matrix;
}

template <class T>
std::vector<T> Hdf5File::read_vector(const std::string& name) const {
  std::vector<hsize_t> dims;
  const Handle dataset = open_stored(file_id_, path_, name, 1, "a 1-D vector", dims);
  std::vector<T> values;
  resize_to_claim(path_, name, std::to_string(dims[0]), [&] { values.resize(dims[0]); });
  read_numbers(dataset.get(), path_, name, values.size(), values.data());
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
  write_scalar_attribute(file_id_, shown_, object, name, type.get(), padded.data());
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, double value) {
  write_scalar_attribute(file_id_, shown_, object, name, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, std::int64_t value) {
  write_scalar_attribute(file_id_, shown_, object, name, H5T_NATIVE_INT64, &value);
}

bool Hdf5File::has_attribute(const std::string& object, const std::string& name) const {
  return link_exists(file_id_, object) &&
         H5Aexists_by_name(file_id_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string Hdf5File::read_string_attribute(const std::string& object, const std::string& name) const {
  const std::string label = where(path_, object + "@" + name);
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  CONTACTNN_REQUIRE_AS(FormatError, H5Tget_class(type.get()) == H5T_STRING,
                       "attribute " << label << " is " << type_text(type.get()) << ", expected a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    // h5py's default for a str: a variable-length (UTF-8) string. HDF5 allocates the value; reclaim it.
    Handle memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memory_type.get(), H5T_VARIABLE);
    H5Tset_cset(memory_type.get(), H5Tget_cset(type.get()));
    char* text = nullptr;
    CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), memory_type.get(), &text) >= 0,
                         "cannot read attribute " << label << " (truncated or corrupt)");
    std::string value = text != nullptr ? std::string(text) : std::string();
    const Handle space(H5Aget_space(attribute.get()), H5Sclose);
    H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, &text);
    return value;
  }
  // An attribute cannot be longer than the file: a larger size is a corrupt header, not an allocation.
  hsize_t file_size = 0;
  H5Fget_filesize(file_id_, &file_size);
  const std::size_t size = H5Tget_size(type.get());
  CONTACTNN_REQUIRE_AS(
      FormatError, size <= file_size,
      "attribute " << label << " claims " << size << " bytes in a file of " << file_size << " (corrupt)");
  std::string value(size, '\0');
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), type.get(), value.data()) >= 0,
                       "cannot read attribute " << label);
  // Null-padded or null-terminated: the value ends at the first NUL. Space-padded (Fortran): trailing blanks
  // are padding.
  value.resize(std::min(value.find('\0'), value.size()));
  if (H5Tget_strpad(type.get()) == H5T_STR_SPACEPAD) value.resize(value.find_last_not_of(' ') + 1);
  return value;
}

double Hdf5File::read_double_attribute(const std::string& object, const std::string& name) const {
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  CONTACTNN_REQUIRE_AS(FormatError,
                       H5Tget_class(type.get()) == H5T_FLOAT || H5Tget_class(type.get()) == H5T_INTEGER,
                       "attribute " << where(path_, object + "@" + name) << " is " << type_text(type.get())
                                    << ", expected a number");
  double value = 0.0;
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value) >= 0,
                       "cannot read attribute " << where(path_, object + "@" + name));
  return value;
}

std::int64_t Hdf5File::read_int_attribute(const std::string& object, const std::string& name) const {
  Handle attribute = open_attribute(file_id_, path_, object, name);
  Handle type(H5Aget_type(attribute.get()), H5Tclose);
  const std::string label = where(path_, object + "@" + name);
  if (H5Tget_class(type.get()) == H5T_ENUM) {
    // numpy's bool, as h5py stores it: an enum over an integer, FALSE = 0 and TRUE = 1. Read as the enum's
    // native form, then as the integer of its width and sign.
    const Handle base(H5Tget_super(type.get()), H5Tclose);
    const Handle memory_type(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), H5Tclose);
    const std::size_t size = memory_type.valid() ? H5Tget_size(memory_type.get()) : 0;
    CONTACTNN_REQUIRE_AS(FormatError,
                         base.valid() && H5Tget_class(base.get()) == H5T_INTEGER && size >= 1 && size <= 8,
                         "attribute " << label << " is an enum that is not over an integer");
    unsigned char raw[8] = {};
    CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), memory_type.get(), raw) >= 0,
                         "cannot read attribute " << label);
    const bool is_signed = H5Tget_sign(base.get()) != H5T_SGN_NONE;
    switch (size) {
      case 1: return native_integer<std::int8_t, std::uint8_t>(raw, is_signed);
      case 2: return native_integer<std::int16_t, std::uint16_t>(raw, is_signed);
      case 4: return native_integer<std::int32_t, std::uint32_t>(raw, is_signed);
      default: {
        std::int64_t s64;
        std::memcpy(&s64, raw, 8);
        return s64;
      }
    }
  }
  CONTACTNN_REQUIRE_AS(FormatError, H5Tget_class(type.get()) == H5T_INTEGER,
                       "attribute " << label << " is " << type_text(type.get()) << ", expected an integer");
  std::int64_t value = 0;
  CONTACTNN_REQUIRE_AS(FormatError, H5Aread(attribute.get(), H5T_NATIVE_INT64, &value) >= 0,
                       "cannot read attribute " << label);
  return value;
}

void require_file_kind(const Hdf5File& file, std::string_view expected_kind, std::int64_t expected_version) {
  const std::string path = file.path().string();
  CONTACTNN_REQUIRE_AS(FormatError, file.has_attribute("/", "kind"),
                       "'" << path
                           << "' is not a contactnn file: root attribute 'kind' is missing (expected '"
                           << expected_kind << "')");
  const std::string kind = file.read_string_attribute("/", "kind");
  CONTACTNN_REQUIRE_AS(FormatError, kind == expected_kind,
                       "'" << path << "' is a " << kind << " file, expected a " << expected_kind << " file");
  CONTACTNN_REQUIRE_AS(
      FormatError, file.has_attribute("/", "schema_version"),
      "'" << path << "': root attribute 'schema_version' is missing (expected " << expected_version << ")");
  const std::int64_t version = file.read_int_attribute("/", "schema_version");
  CONTACTNN_REQUIRE_AS(FormatError, version == expected_version,
                       "'" << path << "' has " << expected_kind << " schema version " << version
                           << ", expected " << expected_version);
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
