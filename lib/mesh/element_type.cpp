#include "mesh/element_type.hpp"

#include <array>
#include <cctype>

namespace contactnn::mesh {

namespace {

// The manuals' tables (header comment), minus one on every node number.
constexpr std::array<std::array<int, 4>, 6> kHexFaces = {
    {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}}};
constexpr std::array<std::array<int, 4>, 5> kWedgeFaces = {
    {{0, 1, 2, -1}, {3, 5, 4, -1}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}}};
constexpr std::array<std::array<int, 3>, 4> kTetFaces = {{{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}}};
// The edges of the header's mid-side tables, in the order of the mid-side nodes (0-based corners).
constexpr std::array<std::array<int, 2>, 12> kHexEdges = {
    {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
constexpr std::array<std::array<int, 2>, 9> kWedgeEdges = {
    {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}, {0, 3}, {1, 4}, {2, 5}}};
constexpr std::array<std::array<int, 2>, 6> kTetEdges = {{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};

template <std::size_t N>
int find_edge(const std::array<std::array<int, 2>, N>& edges, int corners, int a, int b) {
  for (std::size_t k = 0; k < N; ++k) {
    if ((edges[k][0] == a && edges[k][1] == b) || (edges[k][0] == b && edges[k][1] == a)) {
      return corners + static_cast<int>(k);
    }
  }
  return -1;
}

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

}  // namespace

ElementType element_type(std::string_view name) {
  ElementType type;
  type.name.reserve(name.size());
  for (char c : name) type.name.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  const std::string& n = type.name;
  // Longer prefixes first: C3D20 before C3D2..., C3D10 before C3D1...
  if (starts_with(n, "C3D20")) {
    type = {n, ElementShape::kHexahedron, 20, 6, n == "C3D20" || n == "C3D20R"};
  } else if (starts_with(n, "C3D15")) {
    type = {n, ElementShape::kWedge, 15, 5, false};
  } else if (starts_with(n, "C3D10")) {
    type = {n, ElementShape::kTetrahedron, 10, 4, false};
  } else if (starts_with(n, "C3D8")) {
    type = {n, ElementShape::kHexahedron, 8, 6, n == "C3D8" || n == "C3D8R" || n == "C3D8I"};
  } else if (n == "C3D6") {
    type = {n, ElementShape::kWedge, 6, 5, false};
  } else if (n == "C3D4") {
    type = {n, ElementShape::kTetrahedron, 4, 4, false};
  }
  return type;
}

std::span<const int> face_corner_indices(ElementShape shape, int face) {
  switch (shape) {
    case ElementShape::kHexahedron:
      if (face >= 1 && face <= 6) return {kHexFaces[static_cast<std::size_t>(face - 1)].data(), 4};
      break;
    case ElementShape::kWedge:
      if (face >= 1 && face <= 5) {
        const auto& f = kWedgeFaces[static_cast<std::size_t>(face - 1)];
        return {f.data(), f[3] < 0 ? 3u : 4u};
      }
      break;
    case ElementShape::kTetrahedron:
      if (face >= 1 && face <= 4) return {kTetFaces[static_cast<std::size_t>(face - 1)].data(), 3};
      break;
    case ElementShape::kOther: break;
  }
  return {};
}

int quadratic_node_count(ElementShape shape) {
  switch (shape) {
    case ElementShape::kHexahedron: return 20;
    case ElementShape::kWedge: return 15;
    case ElementShape::kTetrahedron: return 10;
    case ElementShape::kOther: break;
  }
  return 0;
}

int corner_node_count(ElementShape shape) {
  switch (shape) {
    case ElementShape::kHexahedron: return 8;
    case ElementShape::kWedge: return 6;
    case ElementShape::kTetrahedron: return 4;
    case ElementShape::kOther: break;
  }
  return 0;
}

int midside_node_index(ElementShape shape, int a, int b) {
  switch (shape) {
    case ElementShape::kHexahedron: return find_edge(kHexEdges, 8, a, b);
    case ElementShape::kWedge: return find_edge(kWedgeEdges, 6, a, b);
    case ElementShape::kTetrahedron: return find_edge(kTetEdges, 4, a, b);
    case ElementShape::kOther: break;
  }
  return -1;
}

}  // namespace contactnn::mesh
