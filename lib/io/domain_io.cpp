#include "io/domain_io.hpp"

#include "core/error.hpp"

namespace contactnn::io {

void write_filters(Hdf5File& file, const std::string& group, const geometry::DomainFilters& f) {
  // Attributes need an object to sit on: an empty marker dataset makes the group exist.
  if (!file.has_dataset(group + "/filters")) file.write_vector<std::uint8_t>(group + "/filters", {});
  const std::string object = group + "/filters";
  file.write_attribute(object, "xy_limit", f.xy_limit);
  file.write_attribute(object, "z_limit", f.z_limit);
  file.write_attribute(object, "ad_not_longer_than_ab", std::int64_t{f.ad_not_longer_than_ab});
  file.write_attribute(object, "nearest_node_a", std::int64_t{f.nearest_node_a});
  file.write_attribute(object, "segment_test_a", std::int64_t{f.segment_test_a});
  file.write_attribute(object, "convex", std::int64_t{f.convex});
  file.write_attribute(object, "min_angle_degrees", f.min_angle_degrees);
  file.write_attribute(object, "max_angle_degrees", f.max_angle_degrees);
  file.write_attribute(object, "max_normal_tilt_tangent", f.max_normal_tilt_tangent);
}

geometry::DomainFilters read_filters(const Hdf5File& file, const std::string& group) {
  const std::string object = group + "/filters";
  geometry::DomainFilters f;
  f.xy_limit = file.read_double_attribute(object, "xy_limit");
  f.z_limit = file.read_double_attribute(object, "z_limit");
  f.ad_not_longer_than_ab = file.read_int_attribute(object, "ad_not_longer_than_ab") != 0;
  f.nearest_node_a = file.read_int_attribute(object, "nearest_node_a") != 0;
  f.segment_test_a = file.read_int_attribute(object, "segment_test_a") != 0;
  f.convex = file.read_int_attribute(object, "convex") != 0;
  f.min_angle_degrees = file.read_double_attribute(object, "min_angle_degrees");
  f.max_angle_degrees = file.read_double_attribute(object, "max_angle_degrees");
  f.max_normal_tilt_tangent = file.read_double_attribute(object, "max_normal_tilt_tangent");
  return f;
}

void write_domain(Hdf5File& file, const std::string& group, const geometry::TrainingDomain& domain) {
  file.write_vector(group + "/feature_min", domain.feature_min);
  file.write_vector(group + "/feature_max", domain.feature_max);
  write_filters(file, group, domain.filters);
  file.write_attribute(group + "/filters", "surface", std::string(to_string(domain.surface)));
}

geometry::TrainingDomain read_domain(const Hdf5File& file, const std::string& group) {
  geometry::TrainingDomain domain;
  domain.surface = read_surface_attribute(file, group + "/filters", "surface");
  domain.feature_min = file.read_vector<double>(group + "/feature_min");
  domain.feature_max = file.read_vector<double>(group + "/feature_max");
  const auto expected = static_cast<std::size_t>(feature_count(domain.surface));
  CONTACTNN_REQUIRE_AS(
      FormatError, domain.feature_min.size() == expected && domain.feature_max.size() == expected,
      "'" << file.path().string() << "', '" << group << "': domain has " << domain.feature_min.size() << "/"
          << domain.feature_max.size() << " feature bounds, expected " << expected << " for "
          << to_string(domain.surface));
  domain.filters = read_filters(file, group);
  return domain;
}

}  // namespace contactnn::io
