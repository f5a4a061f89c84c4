#include "io/dataset_file.hpp"

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/domain_io.hpp"
#include "io/hdf5_file.hpp"

namespace contactnn::io {

namespace {
std::string feature_names(SurfaceKind kind) {
  std::string names;
  for (int i = 0; i < feature_count(kind); ++i) {
    if (i > 0) names += ',';
    names += kFeatureNames[static_cast<std::size_t>(i)];
  }
  return names;
}
}  // namespace

std::unique_ptr<AtomicOutput> write_dataset_uncommitted(const std::filesystem::path& path,
                                                        const dataset::LabelledSet& set) {
  set.validate("dataset to write to '" + path.string() + "'");
  auto output = std::make_unique<AtomicOutput>(path);
  {
    Hdf5File file(output->write_path(), Hdf5File::Mode::kCreate, path);
    file.write_attribute("/", "kind", std::string(kDatasetFileKind));
    file.write_attribute("/", "schema_version", std::int64_t{kDatasetSchemaVersion});
    file.write_attribute("/", "surface", std::string(to_string(set.surface)));
    file.write_attribute("/", "count", static_cast<std::int64_t>(set.size()));
    file.write_attribute("/", "feature_names", feature_names(set.surface));
    file.write_attribute("/", "config", set.config_toml);
    file.write_matrix("features", set.features);
    file.write_matrix("labels", set.labels);
    file.write_vector("gap", std::vector<double>(set.gap.data(), set.gap.data() + set.gap.size()));
    file.write_vector("iterations", std::vector<std::int32_t>(set.iterations.data(),
                                                              set.iterations.data() + set.iterations.size()));
    std::vector<std::uint8_t> status(set.status.size());
    for (std::size_t i = 0; i < status.size(); ++i) status[i] = static_cast<std::uint8_t>(set.status[i]);
    file.write_vector("status", status);
    file.write_vector("scale", std::vector<double>(set.scale.data(), set.scale.data() + set.scale.size()));
    write_filters(file, "domain", set.filters);
    file.close();
  }
  return output;
}

void write_dataset(const std::filesystem::path& path, const dataset::LabelledSet& set) {
  write_dataset_uncommitted(path, set)->commit();
}

dataset::LabelledSet read_dataset(const std::filesystem::path& path) {
  const Hdf5File file(path, Hdf5File::Mode::kRead);
  require_file_kind(file, kDatasetFileKind, kDatasetSchemaVersion);
  dataset::LabelledSet set;
  set.surface = read_surface_attribute(file, "/", "surface");
  set.config_toml = file.read_string_attribute("/", "config");
  set.features = file.read_matrix<double>("features");
  set.labels = file.read_matrix<double>("labels");
  const auto gap = file.read_vector<double>("gap");
  const auto iterations = file.read_vector<std::int32_t>("iterations");
  const auto status = file.read_vector<std::uint8_t>("status");
  const auto scale = file.read_vector<double>("scale");
  set.gap = Eigen::Map<const Eigen::VectorXd>(gap.data(), static_cast<Eigen::Index>(gap.size()));
  set.iterations =
      Eigen::Map<const Eigen::VectorXi>(iterations.data(), static_cast<Eigen::Index>(iterations.size()));
  set.scale = Eigen::Map<const Eigen::VectorXd>(scale.data(), static_cast<Eigen::Index>(scale.size()));
  set.status.resize(status.size());
  for (std::size_t i = 0; i < status.size(); ++i) {
    CONTACTNN_REQUIRE_AS(FormatError, status[i] < kStatusCount,
                         "'" << path.string() << "', 'status' row " << i << ": " << int{status[i]}
                             << " is not a status code (expected 0.." << kStatusCount - 1 << ")");
    set.status[i] = static_cast<Status>(status[i]);
  }
  set.filters = read_filters(file, "domain");
  const auto count = file.read_int_attribute("/", "count");
  CONTACTNN_REQUIRE_AS(FormatError, count == set.size(),
                       "'" << path.string() << "': attribute count = " << count << " but /features has "
                           << set.size() << " rows");
  set.validate("'" + path.string() + "'");
  return set;
}

}  // namespace contactnn::io
