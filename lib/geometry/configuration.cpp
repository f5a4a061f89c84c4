#include "geometry/configuration.hpp"

namespace contactnn::geometry {

bool Configuration::is_finite(bool with_normals) const {
  bool finite = slave.allFinite();
  for (int i = 0; i < 4; ++i) {
    finite = finite && nodes[i].allFinite();
    if (with_normals) finite = finite && normals[i].allFinite();
  }
  return finite;
}

}  // namespace contactnn::geometry
