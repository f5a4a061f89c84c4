#include "core/conventions.hpp"

#include "core/error.hpp"

namespace contactnn {

namespace {
constexpr std::array<std::string_view, kStatusCount> kStatusNames = {
    "ok", "outside", "no_convergence", "degenerate", "invalid", "out_of_domain", "no_segment"};
}

std::string_view to_string(Status status) { return kStatusNames.at(static_cast<std::size_t>(status)); }

std::optional<Status> status_from_string(std::string_view name) {
  for (std::size_t i = 0; i < kStatusNames.size(); ++i) {
    if (kStatusNames[i] == name) return static_cast<Status>(i);
  }
  return std::nullopt;
}

std::string_view to_string(SurfaceKind kind) {
  return kind == SurfaceKind::kBilinear ? "bilinear" : "gregory";
}

std::string_view to_string(Location location) {
  switch (location) {
    case Location::kFace: return "face";
    case Location::kEdge: return "edge";
    case Location::kVertex: return "vertex";
  }
  return "face";
}

SurfaceKind surface_from_string(std::string_view name) {
  if (name == "bilinear") return SurfaceKind::kBilinear;
  if (name == "gregory") return SurfaceKind::kGregory;
  throw InvalidArgument("unknown surface '" + std::string(name) + "': expected 'bilinear' or 'gregory'");
}

}  // namespace contactnn
