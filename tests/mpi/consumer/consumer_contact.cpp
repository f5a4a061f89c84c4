// A C++ consumer of the installed contact search handle (contactnn::contact::ContactSearch): a plate of two
// unit quad4 faces at z = 0 and two slave nodes 0.25 above the centres of its faces. Prints PASS when each
// finds its face with gap 0.25, the point below it and the normal +z.
#include <cmath>
#include <contactnn/contact/contact_search.hpp>
#include <cstdio>
#include <vector>

int main() {
  using namespace contactnn;
  // Nodes 1..6: (0,0) (1,0) (2,0) (0,1) (1,1) (2,1); slave nodes 7, 8.
  const std::vector<mesh::FaceType> types{mesh::FaceType::kQuad4, mesh::FaceType::kQuad4};
  const std::vector<long> connectivity{1, 2, 5, 4, 2, 3, 6, 5};
  const std::vector<double> x{0, 0, 0, 1, 0, 0, 2,   0,   0,    0,   1,   0,
                              1, 1, 0, 2, 1, 0, 0.5, 0.5, 0.25, 1.5, 0.5, 0.25};
  const std::vector<long> slaves{7, 8};
  contact::ContactSearch search(types, connectivity, contact::NodeNumbering{8, 1, {}},
                                contact::SlavePoints{slaves, 0}, contact::ContactSearchOptions{});
  std::vector<int> status(2), face(2), location(2);
  std::vector<double> param(4), point(6), gap(2), normal(6);
  search.update(x, {}, {status, face, location, param, point, gap, normal});
  bool ok = true;
  for (int i = 0; i < 2; ++i) {
    const auto u = static_cast<std::size_t>(i);
    ok = ok && status[u] == 0 && face[u] == i && std::abs(gap[u] - 0.25) < 1e-12 &&
         std::abs(point[3 * u] - (0.5 + i)) < 1e-12 && std::abs(point[3 * u + 1] - 0.5) < 1e-12 &&
         std::abs(normal[3 * u + 2] - 1.0) < 1e-12;
    std::printf("slave %d: status %d face %d gap %.17g\n", i, status[u], face[u], gap[u]);
  }
  std::printf(ok ? "PASS: contactnn::contact::ContactSearch from the installed package\n" : "FAIL\n");
  return ok ? 0 : 1;
}
