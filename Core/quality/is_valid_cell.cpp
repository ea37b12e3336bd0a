// The valid-cell test: the tets over four nodes of a cell, oriented on the
// reference cell, all positive.
#include "quality/is_valid_cell.h"

#include "geometry/predicates.h"

#include <array>
#include <cstdint>
#include <vector>

namespace femorph {
namespace {

using NodeTet = std::array<std::int8_t, 4>;

// Reference cells of hex/hex_decomposition_types.h (VTK node orders,
// positive orientation).
const Vec3 kHexReference[8] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                               Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
const Vec3 kWedgeReference[6] = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0),
                                 Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 0, 1)};
const Vec3 kPyramidReference[5] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                   Vec3(0.5, 0.5, 1)};

// Every set of four nodes not coplanar on the reference cell, ordered so that
// it is positive there (two nodes swapped where it was negative).
std::vector<NodeTet> node_tets(const Vec3* reference, int n) {
  std::vector<NodeTet> tets;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c)
        for (int d = c + 1; d < n; ++d) {
          const int sign = orient3d_sign(reference[a], reference[b], reference[c], reference[d]);
          if (sign == 0) continue;
          tets.push_back(sign > 0 ? NodeTet{{std::int8_t(a), std::int8_t(b), std::int8_t(c), std::int8_t(d)}}
                                  : NodeTet{{std::int8_t(b), std::int8_t(a), std::int8_t(c), std::int8_t(d)}});
        }
  return tets;
}

const std::vector<NodeTet>& tets_of(CellKind kind) {
  static const std::vector<NodeTet> hex = node_tets(kHexReference, 8);
  static const std::vector<NodeTet> wedge = node_tets(kWedgeReference, 6);
  static const std::vector<NodeTet> pyramid = node_tets(kPyramidReference, 5);
  static const std::vector<NodeTet> tet = {NodeTet{{0, 1, 2, 3}}};
  switch (kind) {
    case CellKind::Hexahedron: return hex;
    case CellKind::Wedge: return wedge;
    case CellKind::Pyramid: return pyramid;
    case CellKind::Tetra: break;
  }
  return tet;
}

}  // namespace

bool is_valid_cell(CellKind kind, const Vec3* points) {
  for (const NodeTet& t : tets_of(kind))
    if (orient3d_sign(points[t[0]], points[t[1]], points[t[2]], points[t[3]]) <= 0) return false;
  return true;
}

}  // namespace femorph
