#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "core/error.hpp"
#include "error_message.hpp"
#include "io/dataset_file.hpp"
#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

std::filesystem::path temp_dir() { return testing::test_output_dir("test-io"); }

dataset::LabelledSet small_set() {
  dataset::LabelledSet set;
  set.resize(5, SurfaceKind::kBilinear);
  for (Eigen::Index i = 0; i < 5; ++i) {
    for (Eigen::Index f = 0; f < 8; ++f)
      set.features(i, f) = 0.1 * static_cast<double>(i) - 0.01 * static_cast<double>(f);
    set.labels(i, 0) = -0.5 + 0.1 * static_cast<double>(i);
    set.labels(i, 1) = 0.3 / (1.0 + static_cast<double>(i));
    set.gap[i] = 0.01 * static_cast<double>(i);
    set.iterations[i] = static_cast<int>(i) + 3;
    set.status[static_cast<std::size_t>(i)] = i == 4 ? Status::kOutside : Status::kOk;
    set.scale[i] = 1.0;
  }
  set.config_toml = "[gen-configs]\nd_xy_points=4\n";
  set.filters.min_angle_degrees = 12.5;
  return set;
}

std::string error_of(const std::filesystem::path& path) {
  return testing::error_message<Error>([&] { (void)read_dataset(path); });
}

TEST(DatasetFile, RoundTripIsExact) {
  const auto path = temp_dir() / "round.h5";
  const dataset::LabelledSet set = small_set();
  write_dataset(path, set);
  const dataset::LabelledSet back = read_dataset(path);
  EXPECT_EQ(back.surface, set.surface);
  EXPECT_TRUE(back.features == set.features);  // bit-exact, not approximate
  EXPECT_TRUE(back.labels == set.labels);
  EXPECT_TRUE(back.gap == set.gap);
  EXPECT_TRUE(back.iterations == set.iterations);
  EXPECT_EQ(back.status, set.status);
  EXPECT_EQ(back.config_toml, set.config_toml);
  EXPECT_EQ(back.filters.min_angle_degrees, 12.5);
  EXPECT_EQ(back.filters.nearest_node_a, set.filters.nearest_node_a);
}

TEST(DatasetFile, SameContentGivesTheSameBytes) {
  const auto a = temp_dir() / "same-a.h5", b = temp_dir() / "same-b.h5";
  write_dataset(a, small_set());
  write_dataset(b, small_set());
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(fa)), {}),
      sb((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_EQ(sa, sb);
}

TEST(DatasetFile, WrongSchemaVersionKindOrShapeIsRejectedWithBothSides) {
  const auto path = temp_dir() / "bad.h5";
  {
    write_dataset(path, small_set());
    Hdf5File f(path, Hdf5File::Mode::kCreate);  // rewrite with a future version
    f.write_attribute("/", "kind", std::string(kDatasetFileKind));
    f.write_attribute("/", "schema_version", std::int64_t{99});
  }
  std::string e = error_of(path);
  EXPECT_NE(e.find("schema version 99, expected 1"), std::string::npos) << e;
  EXPECT_NE(e.find("bad.h5"), std::string::npos) << e;
  {
    Hdf5File f(path, Hdf5File::Mode::kCreate);
    f.write_attribute("/", "kind", std::string(kNetworkFileKind));
    f.write_attribute("/", "schema_version", std::int64_t{1});
  }
  e = error_of(path);
  EXPECT_NE(e.find("is a contactnn-network file, expected a contactnn-dataset file"), std::string::npos) << e;
  {
    // A dataset whose features have 7 columns: a bilinear dataset needs 8.
    dataset::LabelledSet set = small_set();
    Hdf5File f(path, Hdf5File::Mode::kCreate);
    f.write_attribute("/", "kind", std::string(kDatasetFileKind));
    f.write_attribute("/", "schema_version", std::int64_t{kDatasetSchemaVersion});
    f.write_attribute("/", "surface", std::string("bilinear"));
    f.write_attribute("/", "count", std::int64_t{5});
    f.write_attribute("/", "config", std::string());
    f.write_matrix("features", MatrixRM<double>(set.features.leftCols(7)));
    f.write_matrix("labels", set.labels);
    f.write_vector("gap", std::vector<double>(5, 0.0));
    f.write_vector("iterations", std::vector<std::int32_t>(5, 1));
    f.write_vector("status", std::vector<std::uint8_t>(5, 0));
    f.write_vector("scale", std::vector<double>(5, 1.0));
    f.write_vector<std::uint8_t>("domain/filters", {});
  }
  e = error_of(path);
  EXPECT_NE(e.find("attribute"), std::string::npos) << e;  // filters' attributes missing are named
}

TEST(DatasetFile, AnOkRowOutsideTheDomainOrBeyondTheFloatRangeIsAFormatError) {
  // Finite but impossible values of an ok row: a label outside the domain (evaluate-net reported a mean error
  // of 3e296 with exit 0) or a feature beyond the float range (train-net's float cast made it inf: an
  // internal error, exit 2). Both are a corrupt file: FormatError naming the file and the row.
  const auto path = temp_dir() / "impossible.h5";
  const struct {
    Eigen::Index row, column;
    bool feature;
    double value;
    const char* says;
  } cases[] = {{2, 0, false, 1e300, "row 2 has status ok but label 0 = 1e+300"},
               {1, 1, false, -1.5, "row 1 has status ok but label 1 = -1.5"},
               {3, 5, true, 1.7e308, "row 3 has a feature beyond the float range"}};
  for (const auto& c : cases) {
    // write_dataset refuses such a set: a valid file with a marker value, then its 8 bytes replaced in place.
    dataset::LabelledSet set = small_set();
    const double marker = 0.123456789012345;
    (c.feature ? set.features : set.labels)(c.row, c.column) = marker;
    write_dataset(path, set);
    std::string bytes;
    {
      std::ifstream in(path, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string from(reinterpret_cast<const char*>(&marker), sizeof marker);
    const std::size_t at = bytes.find(from);
    ASSERT_NE(at, std::string::npos) << "the marker value is stored as it is";
    ASSERT_EQ(bytes.find(from, at + 1), std::string::npos) << "the marker value is stored once";
    bytes.replace(at, sizeof marker, std::string(reinterpret_cast<const char*>(&c.value), sizeof c.value));
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    const std::string e = error_of(path);
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
    EXPECT_THROW((void)read_dataset(path), FormatError);
  }
  // The same value in a row whose status is not ok is data, not a contradiction.
  dataset::LabelledSet set = small_set();
  set.labels(4, 0) = 1e300;
  write_dataset(path, set);
  EXPECT_NO_THROW((void)read_dataset(path));
}

TEST(DatasetFile, TruncatedOrForeignFilesAreFormatErrorsAndMissingFilesIoErrors) {
  const auto path = temp_dir() / "truncated.h5";
  write_dataset(path, small_set());
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  EXPECT_THROW((void)read_dataset(path), FormatError);
  const auto text = temp_dir() / "text.h5";
  std::ofstream(text) << "ax,ay\n1,2\n";
  const std::string e = error_of(text);
  EXPECT_NE(e.find("not an HDF5 file"), std::string::npos) << e;
  EXPECT_THROW((void)read_dataset(temp_dir() / "does-not-exist.h5"), IoError);
}

TEST(DatasetFile, AWriteThatFailsLeavesNoFileBehind) {
  const auto path = temp_dir() / "never.h5";
  std::filesystem::remove(path);
  dataset::LabelledSet set = small_set();
  set.labels(0, 0) = std::nan("");  // status ok with a NaN label: refused before anything is written
  EXPECT_THROW(write_dataset(path, set), FormatError);
  EXPECT_FALSE(std::filesystem::exists(path));
  for (const auto& entry : std::filesystem::directory_iterator(temp_dir())) {
    EXPECT_EQ(
        entry.path().extension() == ".tmp" && entry.path().string().find("never.h5") != std::string::npos,
        false);
  }
}

}  // namespace
}  // namespace contactnn::io
