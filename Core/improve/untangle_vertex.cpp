// Vertex relocation fallback for the inverted element removal (thesis 2.6.2).
#include "improve/untangle_vertex.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace femorph {

bool untangle_vertex(TetMesh& mesh, index_t v, const ProjectVertexFn& project) {
  if (!mesh.vertex_alive(v)) return false;
  const VertexClass cls = mesh.vertex_class(v);
  if (cls == VertexClass::Curve || cls == VertexClass::Corner) return false;
  thread_local std::vector<index_t> ball, around;
  const Vec3 p = mesh.point(v);
  Vec3 target = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // plane of the boundary faces (surface vertex)
  bool planar = true;
  if (cls == VertexClass::Inner) {
    mesh.vertex_neighbors(v, around);
  } else {
    // Other vertices of v's boundary faces, and whether the faces are coplanar.
    mesh.vertex_ball(v, ball);
    around.clear();
    for (index_t t : ball) {
      const int lv = mesh.local_index(t, v);
      const Tet& T = mesh.tet(t);
      for (int f = 0; f < 4; ++f) {
        if (f == lv || !mesh.is_boundary_face(t, f)) continue;
        const Vec3& a = mesh.point(T[kTetFace[f][0]]);
        const Vec3 n = (mesh.point(T[kTetFace[f][1]]) - a).cross(mesh.point(T[kTetFace[f][2]]) - a);
        if (normal.isZero()) normal = n;
        else if (n.cross(normal).norm() > 1e-9 * n.norm() * normal.norm()) planar = false;
        for (int k = 0; k < 3; ++k)
          if (T[kTetFace[f][k]] != v) around.push_back(T[kTetFace[f][k]]);
      }
    }
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    if (normal.isZero() || (!planar && !project)) return false;
    normal.normalize();
  }
  if (around.empty()) return false;
  for (index_t w : around) target += mesh.point(w);
  target /= static_cast<double>(around.size());
  auto try_move = [&](Vec3 q) {
    if (cls == VertexClass::Surface) {
      if (planar) q -= (q - p).dot(normal) * normal;  // stay in the face plane
      else q = project(v, q);
    }
    return mesh.move_vertex(v, q) == OpStatus::Ok;
  };
  for (double lambda : {1.0, 0.5, 0.25})
    if (try_move(p + lambda * (target - p))) return true;
  return false;
}

}  // namespace femorph
