#include "core/conventions.hpp"

#include "core/enum_names.hpp"
#include "core/error.hpp"

namespace contactnn {

namespace {
constexpr std::array<std::string_view, kStatusCount> kStatusNames = {
    "ok", "outside", "no_convergence", "degenerate", "invalid", "out_of_domain", "no_segment"};
constexpr std::array<std::string_view, 2> kSurfaceNames = {"bilinear", "gregory"};
constexpr std::array<std::string_view, 3> kLocationNames = {"face", "edge", "vertex"};
}  // namespace

std::string_view to_string(Status status) { return kStatusNames.at(static_cast<std::size_t>(status)); }

std::optional<Status> status_from_string(std::string_view name) {
  return enum_from_name<Status>(kStatusNames, name);
}

std::string_view to_string(SurfaceKind kind) {
  return kind == SurfaceKind::kBilinear ? kSurfaceNames[0] : kSurfaceNames[1];
}

std::string_view to_string(Location location) { return enum_name(kLocationNames, location, "face"); }

SurfaceKind surface_from_string(std::string_view name) {
  if (const auto kind = enum_from_name<SurfaceKind>(kSurfaceNames, name)) return *kind;
  throw InvalidArgument("unknown surface '" + std::string(name) + "': expected 'bilinear' or 'gregory'");
}

}  // namespace contactnn
