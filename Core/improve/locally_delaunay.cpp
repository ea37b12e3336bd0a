// Local Delaunay test and circumcentre (thesis 2.6.5.4, Eq. 2.27-2.28).
#include "improve/locally_delaunay.h"

#include "geometry/predicates.h"
#include "mesh/tet_mesh.h"

#include <cmath>

namespace femorph {

bool locally_delaunay(const TetMesh& mesh, index_t t) {
  const Tet& T = mesh.tet(t);
  for (int f = 0; f < 4; ++f) {
    const index_t code = mesh.adjacency(t, f);
    if (code < 0) continue;
    const index_t e = mesh.tet(code >> 2)[code & 3];
    if (insphere_sign(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]), mesh.point(e)) > 0)
      return false;
  }
  return true;
}

bool tet_circumcentre(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Vec3* centre) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double det = u.dot(v.cross(w));
  const double scale = u.squaredNorm() + v.squaredNorm() + w.squaredNorm();
  // Relative flatness 6V / L^3 below 1e-12: no usable circumcentre.
  if (!(std::abs(det) > 1e-12 * scale * std::sqrt(scale))) return false;
  const Vec3 r = (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v)) / (2 * det);
  *centre = a + r;
  return true;
}

}  // namespace femorph
