// The priority Q_can of a candidate, thesis Eq. 4.1 (after Meshkat & Talmor
// 2000, "dangle" and "fangle", and Botella 2016, gamma_type):
//   Q_can = 1/(2|Q_dec|) sum_q cos theta_da(q)
//         + 1/(2|Q_dec|) sum_q min_{j in q} sin theta_fa(q, j) + gamma_type
// over the candidate's quads q: theta_da the angle between the normals of
// q's two triangles (cos = 1 when coplanar), theta_fa(q, j) the interior
// angle of q at its vertex j; gamma = 10 hexahedron, 4 prism, 0 pyramid.
#include "hex/tet_to_hex_internal.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace tet_to_hex {

double candidate_priority(const SearchTree& tree, const Walk& walk, const Vec3* points) {
  double cos_sum = 0, sin_sum = 0;
  for (int q = 0; q < tree.num_quads; ++q) {
    const auto& l = tree.quads[q];
    const int d = tree.quad_diagonal[q];  // triangles (d, d+1, d+2), (d, d+2, d+3)
    const Vec3& o = points[walk.node[l[d]]];
    const Vec3 b = points[walk.node[l[d + 2]]] - o;
    const Vec3 n1 = (points[walk.node[l[d + 1]]] - o).cross(b);
    const Vec3 n2 = b.cross(points[walk.node[l[(d + 3) % 4]]] - o);
    const double norms = std::sqrt(n1.squaredNorm() * n2.squaredNorm());
    cos_sum += norms > 0 ? n1.dot(n2) / norms : -1.0;
    // min_j sin theta_fa = sqrt(min_j |u x v|^2 / (|u|^2 |v|^2)), u and v
    // the quad's edges at j.
    double min_sin2 = 1.0;
    for (int j = 0; j < 4; ++j) {
      const Vec3& x = points[walk.node[l[j]]];
      const Vec3 u = points[walk.node[l[(j + 3) % 4]]] - x;
      const Vec3 v = points[walk.node[l[(j + 1) % 4]]] - x;
      const double lengths2 = u.squaredNorm() * v.squaredNorm();
      min_sin2 = std::min(min_sin2, lengths2 > 0 ? u.cross(v).squaredNorm() / lengths2 : 0.0);
    }
    sin_sum += std::sqrt(min_sin2);
  }
  double gamma = 0;
  switch (tree.kind) {
    case CellKind::Hexahedron: gamma = 10; break;
    case CellKind::Wedge: gamma = 4; break;
    default: break;
  }
  return (cos_sum + sin_sum) / (2.0 * tree.num_quads) + gamma;
}

}  // namespace tet_to_hex
}  // namespace femorph
