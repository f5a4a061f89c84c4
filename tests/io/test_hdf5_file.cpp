// io::Hdf5File and the dataset and network readers on files written by another tool (issue 12): a dataset
// written the way h5py writes the documented schema (variable-length UTF-8 string attributes, float32
// features, int64 status and iterations, chunked and gzip-compressed datasets, numpy booleans) reads to the
// same values; what is ambiguous is an error naming both sides; a network file whose real_type or activation
// is not supported, and a checkpoint with a non-finite momentum term, are refused as such.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "error_message.hpp"
#include "io/dataset_file.hpp"
#include "io/hdf5_file.hpp"
#include "io/network_file.hpp"
#include "mlp/trainer.hpp"
#include "network_fixtures.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() { return testing::test_output_dir("test-hdf5-file"); }

/// HDF5 handles closed on scope exit (the test's own, independent of the code under test).
struct Id {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Id() {
    if (id >= 0) close(id);
  }
};

/// Writers that mirror what h5py does for `f.attrs[name] = value` and `f.create_dataset(...)`.
void vlen_string_attribute(hid_t object, const char* name, const std::string& value) {
  const Id type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  const Id space{H5Screate(H5S_SCALAR), H5Sclose};
  const Id attribute{H5Acreate2(object, name, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  const char* text = value.c_str();
  ASSERT_GE(H5Awrite(attribute.id, type.id, &text), 0);
}

template <class T>
void scalar_attribute(hid_t object, const char* name, hid_t type, T value) {
  const Id space{H5Screate(H5S_SCALAR), H5Sclose};
  const Id attribute{H5Acreate2(object, name, type, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  ASSERT_GE(H5Awrite(attribute.id, type, &value), 0);
}

/// numpy's bool as h5py stores it: an enum over int8 with FALSE = 0 and TRUE = 1.
void bool_attribute(hid_t object, const char* name, bool value) {
  const Id type{H5Tenum_create(H5T_NATIVE_INT8), H5Tclose};
  const signed char no = 0, yes = 1;
  H5Tenum_insert(type.id, "FALSE", &no);
  H5Tenum_insert(type.id, "TRUE", &yes);
  const signed char v = value ? 1 : 0;
  scalar_attribute(object, name, type.id, v);
}

/// A dataset of `file_type` from `memory_type` data; chunked with shuffle and gzip when `compressed`
/// (h5py's compression="gzip", shuffle=True), with the extra `filter` when it is not 0.
void dataset(hid_t file, const char* name, hid_t file_type, hid_t memory_type, std::vector<hsize_t> dims,
             const void* data, bool compressed, H5Z_filter_t filter = 0) {
  const Id space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
  const Id props{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  if (compressed || filter != 0) {
    std::vector<hsize_t> chunk = dims;
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], 7));
    H5Pset_chunk(props.id, static_cast<int>(chunk.size()), chunk.data());
    if (compressed) {
      H5Pset_shuffle(props.id);
      H5Pset_deflate(props.id, 4);
    }
    if (filter != 0) H5Pset_filter(props.id, filter, 0, 0, nullptr);
  }
  const Id set{H5Dcreate2(file, name, file_type, space.id, H5P_DEFAULT, props.id, H5P_DEFAULT), H5Dclose};
  ASSERT_GE(set.id, 0) << name;
  ASSERT_GE(H5Dwrite(set.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0) << name;
}

/// What an h5py script in the documented schema writes for `n` rows. Values are float32-exact so that the
/// comparison after reading is exact.
struct H5pyDataset {
  static constexpr hsize_t n = 23;
  std::vector<float> features, labels, gap;
  std::vector<std::int64_t> iterations, status;
  std::vector<double> scale;

  H5pyDataset() {
    for (hsize_t i = 0; i < n; ++i) {
      for (int f = 0; f < 8; ++f)
        features.push_back(static_cast<float>(i) * 0.125f - static_cast<float>(f) * 0.5f);
      labels.push_back(-0.5f + 0.0625f * static_cast<float>(i));
      labels.push_back(0.25f);
      gap.push_back(0.03125f * static_cast<float>(i));
      iterations.push_back(static_cast<std::int64_t>(i % 7) + 2);
      status.push_back(static_cast<std::int64_t>(i % 3 == 0 ? 1 : 0));
      scale.push_back(1.0);
    }
  }

  /// Writes the file; `spoil` may replace one member by another type or layout.
  void write(const fs::path& path,
             const std::function<bool(hid_t, const std::string&)>& spoil = nullptr) const {
    const Id file{H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    ASSERT_GE(file.id, 0);
    const auto member = [&](const std::string& name, auto&& write) {
      if (spoil == nullptr || !spoil(file.id, name)) write();
    };
    member("kind", [&] { vlen_string_attribute(file.id, "kind", "contactnn-dataset"); });
    scalar_attribute(file.id, "schema_version", H5T_STD_I64LE, std::int64_t{1});
    member("surface", [&] { vlen_string_attribute(file.id, "surface", "bilinear"); });
    scalar_attribute(file.id, "count", H5T_STD_I64LE, static_cast<std::int64_t>(n));
    vlen_string_attribute(file.id, "feature_names", "xc,yc,zc,xd,yd,xs,ys,zs");
    vlen_string_attribute(file.id, "config", "[gen-configs]\nnote = \"written by h5py, \u00e9t\u00e9\"\n");
    member("features", [&] {
      dataset(file.id, "features", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, {n, 8}, features.data(), true);
    });
    dataset(file.id, "labels", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, {n, 2}, labels.data(), true);
    dataset(file.id, "gap", H5T_IEEE_F32BE, H5T_NATIVE_FLOAT, {n}, gap.data(), false);
    member("iterations", [&] {
      dataset(file.id, "iterations", H5T_STD_I64LE, H5T_NATIVE_INT64, {n}, iterations.data(), true);
    });
    member("status",
           [&] { dataset(file.id, "status", H5T_STD_I64LE, H5T_NATIVE_INT64, {n}, status.data(), false); });
    dataset(file.id, "scale", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n}, scale.data(), true);
    const Id group{H5Gcreate2(file.id, "domain", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    const std::uint8_t nothing = 0;
    dataset(group.id, "filters", H5T_STD_U8LE, H5T_NATIVE_UINT8, {0}, &nothing, false);
    const Id filters{H5Dopen2(group.id, "filters", H5P_DEFAULT), H5Dclose};
    scalar_attribute(filters.id, "xy_limit", H5T_IEEE_F64LE, 2.0);
    scalar_attribute(filters.id, "z_limit", H5T_IEEE_F32LE, 0.25f);
    bool_attribute(filters.id, "ad_not_longer_than_ab", true);
    bool_attribute(filters.id, "nearest_node_a", true);
    bool_attribute(filters.id, "segment_test_a", false);
    scalar_attribute(filters.id, "convex", H5T_STD_I32LE, std::int32_t{1});
    scalar_attribute(filters.id, "min_angle_degrees", H5T_STD_I64LE, std::int64_t{0});
    scalar_attribute(filters.id, "max_angle_degrees", H5T_IEEE_F64LE, 180.0);
    scalar_attribute(filters.id, "max_normal_tilt_tangent", H5T_IEEE_F64LE, 0.2);
  }
};

std::string read_error(const fs::path& path) {
  return testing::error_message<FormatError>([&] { (void)read_dataset(path); });
}

TEST(Hdf5File, ADatasetWrittenAsH5pyWritesItReadsToTheSameValues) {
  const H5pyDataset h5py;
  const fs::path path = temp_dir() / "h5py.h5";
  h5py.write(path);
  const dataset::LabelledSet set = read_dataset(path);
  ASSERT_EQ(set.size(), static_cast<Eigen::Index>(H5pyDataset::n));
  EXPECT_EQ(set.surface, SurfaceKind::kBilinear);
  EXPECT_NE(set.config_toml.find("h5py, \u00e9t\u00e9"), std::string::npos) << set.config_toml;
  for (Eigen::Index i = 0; i < set.size(); ++i) {
    const auto r = static_cast<std::size_t>(i);
    for (int f = 0; f < 8; ++f) EXPECT_EQ(set.features(i, f), static_cast<double>(h5py.features[r * 8 + f]));
    EXPECT_EQ(set.labels(i, 0), static_cast<double>(h5py.labels[2 * r]));
    EXPECT_EQ(set.gap[i], static_cast<double>(h5py.gap[r]));
    EXPECT_EQ(set.iterations[i], h5py.iterations[r]);
    EXPECT_EQ(static_cast<std::int64_t>(set.status[r]), h5py.status[r]);
  }
  EXPECT_EQ(set.filters.z_limit, 0.25);
  EXPECT_TRUE(set.filters.ad_not_longer_than_ab);
  EXPECT_FALSE(set.filters.segment_test_a);
  EXPECT_TRUE(set.filters.convex);
}

TEST(Hdf5File, IntegerFeaturesAreAnErrorNamingBothTypes) {
  const H5pyDataset h5py;
  const fs::path path = temp_dir() / "int-features.h5";
  std::vector<std::int64_t> ints(h5py.features.size(), 1);
  h5py.write(path, [&](hid_t file, const std::string& name) {
    if (name != "features") return false;
    dataset(file, "features", H5T_STD_I64LE, H5T_NATIVE_INT64, {H5pyDataset::n, 8}, ints.data(), false);
    return true;
  });
  const std::string e = read_error(path);
  EXPECT_NE(e.find("'features' is int64, expected floating point"), std::string::npos) << e;
  EXPECT_NE(e.find(path.string()), std::string::npos) << e;
}

TEST(Hdf5File, RealStatusCodesAreAnErrorNotATruncation) {
  const H5pyDataset h5py;
  const fs::path path = temp_dir() / "float-status.h5";
  const std::vector<double> reals(H5pyDataset::n, 0.5);
  h5py.write(path, [&](hid_t file, const std::string& name) {
    if (name != "status") return false;
    dataset(file, "status", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {H5pyDataset::n}, reals.data(), false);
    return true;
  });
  const std::string e = read_error(path);
  EXPECT_NE(e.find("'status' is float64, expected integers"), std::string::npos) << e;
}

TEST(Hdf5File, IntegersBeyondTheSchemaTypeAreAnErrorNotAClamp) {
  const H5pyDataset h5py;
  // 300 in a uint16 status would clamp to 255 under HDF5's own conversion; 2^63 + 5 in a uint64 would
  // clamp to INT64_MAX.
  const fs::path wide = temp_dir() / "wide-status.h5";
  std::vector<std::uint16_t> status(H5pyDataset::n, 0);
  status[4] = 300;
  h5py.write(wide, [&](hid_t file, const std::string& name) {
    if (name != "status") return false;
    dataset(file, "status", H5T_STD_U16LE, H5T_NATIVE_UINT16, {H5pyDataset::n}, status.data(), false);
    return true;
  });
  std::string e = read_error(wide);
  EXPECT_NE(e.find("'status' element 4 is 300, outside the range of uint8"), std::string::npos) << e;

  const fs::path huge = temp_dir() / "huge-iterations.h5";
  std::vector<std::uint64_t> iterations(H5pyDataset::n, 3);
  iterations[2] = (std::uint64_t{1} << 63) + 5;
  h5py.write(huge, [&](hid_t file, const std::string& name) {
    if (name != "iterations") return false;
    dataset(file, "iterations", H5T_STD_U64LE, H5T_NATIVE_UINT64, {H5pyDataset::n}, iterations.data(), false);
    return true;
  });
  e = read_error(huge);
  EXPECT_NE(e.find("'iterations' element 2 is at least 2^63"), std::string::npos) << e;
}

TEST(Hdf5File, AnAttributeArrayIsNotReadAsOneValue) {
  const H5pyDataset h5py;
  const fs::path path = temp_dir() / "array-attribute.h5";
  h5py.write(path, [&](hid_t file, const std::string& name) {
    if (name != "surface") return false;
    const Id type{H5Tcopy(H5T_C_S1), H5Tclose};
    H5Tset_size(type.id, 8);
    const hsize_t three = 3;
    const Id space{H5Screate_simple(1, &three, nullptr), H5Sclose};
    const Id attribute{H5Acreate2(file, "surface", type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    const char values[24] = "bilinearbilineargregory";
    H5Awrite(attribute.id, type.id, values);
    return true;
  });
  const std::string e = read_error(path);
  EXPECT_NE(e.find("'/@surface' holds 3 values, expected one"), std::string::npos) << e;
}

/// A filter that copies its data: registered to write a file that needs it, then unregistered.
std::size_t copy_filter(unsigned, std::size_t, const unsigned[], std::size_t nbytes, std::size_t*, void**) {
  return nbytes;
}

TEST(Hdf5File, AFilterThisLibraryLacksIsNamed) {
  constexpr H5Z_filter_t kFilter = 307;
  const H5Z_class2_t filter_class = {H5Z_CLASS_T_VERS,        kFilter, 1,       1,
                                     "test-only copy filter", nullptr, nullptr, copy_filter};
  ASSERT_GE(H5Zregister(&filter_class), 0);
  const H5pyDataset h5py;
  const fs::path path = temp_dir() / "foreign-filter.h5";
  h5py.write(path, [&](hid_t file, const std::string& name) {
    if (name != "features") return false;
    dataset(file, "features", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, {H5pyDataset::n, 8}, h5py.features.data(),
            false, kFilter);
    return true;
  });
  ASSERT_NO_THROW((void)read_dataset(path));  // readable while the filter exists
  ASSERT_GE(H5Zunregister(kFilter), 0);
  const std::string e = read_error(path);
  EXPECT_NE(e.find("'features' is stored with HDF5 filter 307 ('test-only copy filter')"), std::string::npos)
      << e;
}

// ---------------------------------------------------------------------------------------------------------
// Network files: only what is evaluated is accepted.

using testing::bilinear_domain;

mlp::Network<float> small_network() { return testing::bilinear_network<float>({8, 3, 2}, 2.0, 4); }

/// Replaces root string attribute `name` by `value` (fixed-length, as contactnn writes).
void set_root_string(const fs::path& path, const char* name, const std::string& value) {
  const Id file{H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose};
  ASSERT_GE(file.id, 0);
  H5Adelete(file.id, name);
  vlen_string_attribute(file.id, name, value);
}

std::string network_error(const fs::path& path) {
  return testing::error_message<FormatError>([&] {
    (void)read_network<float>(path);
    (void)read_network_real_type(path);
  });
}

TEST(NetworkFileChecks, AnUnsupportedRealTypeOrActivationIsRefusedByName) {
  const fs::path path = temp_dir() / "net-type.h5";
  write_network(path, small_network(), bilinear_domain(), NetworkProvenance{});
  ASSERT_EQ(network_error(path), "(no error)");
  EXPECT_EQ(read_network_real_type(path), "float32");

  set_root_string(path, "real_type", "float16");
  std::string e = network_error(path);
  EXPECT_NE(e.find("real_type is 'float16', expected 'float32' or 'float64'"), std::string::npos) << e;

  write_network(path, small_network(), bilinear_domain(), NetworkProvenance{});
  set_root_string(path, "activation", "tanh");
  e = network_error(path);
  EXPECT_NE(e.find("activation is 'tanh', expected the sigmoid of Eq 12"), std::string::npos) << e;
}

TEST(NetworkFileChecks, ACheckpointWithANonFiniteMomentumIsCorruptNotADivergence) {
  const fs::path path = temp_dir() / "checkpoint-nan.h5";
  const mlp::Network<float> net = small_network();
  mlp::TrainingState<float> state;
  state.velocity.assign(net.parameter_count(), 0.01f);
  state.best_parameters.assign(net.parameter_count(), 0.5f);
  state.epoch = 6;
  state.best_epoch = 4;
  state.best_validation_loss = 1e-3;
  state.training_loss = 2e-3;
  state.validation_loss = 1.5e-3;
  write_network(path, net, bilinear_domain(), NetworkProvenance{}, &state);
  ASSERT_NO_THROW((void)read_training_state<float>(path, net));
  {
    const Id file{H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose};
    const Id velocity{H5Dopen2(file.id, "checkpoint/velocity", H5P_DEFAULT), H5Dclose};
    std::vector<double> values(net.parameter_count(), 0.01);
    values[5] = std::numeric_limits<double>::quiet_NaN();
    ASSERT_GE(H5Dwrite(velocity.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  }
  try {
    (void)read_training_state<float>(path, net);
    FAIL() << "a NaN momentum term was accepted";
  } catch (const FormatError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("checkpoint/velocity element 5 is nan: the checkpoint is corrupt"), std::string::npos)
        << m;
    EXPECT_EQ(m.find("learning"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace contactnn::io
