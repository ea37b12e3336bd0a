// Quality after an edge collapse (thesis 2.6.2: collapses chosen by the
// minimum stretch of the tets around the new vertex, Fig. 2.39).
#include "improve/collapse_min_stretch.h"

#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace femorph {

double collapse_min_stretch(const TetMesh& mesh, index_t keep, index_t remove, const Vec3& position) {
  thread_local std::vector<index_t> ball;
  double q = std::numeric_limits<double>::infinity();
  auto add = [&](const Tet& T) {
    const Vec3* p[4];
    for (int i = 0; i < 4; ++i) p[i] = (T[i] == keep || T[i] == remove) ? &position : &mesh.point(T[i]);
    q = std::min(q, tet_stretch(*p[0], *p[1], *p[2], *p[3]));
  };
  mesh.vertex_ball(remove, ball);
  for (index_t t : ball)
    if (mesh.local_index(t, keep) < 0) add(mesh.tet(t));  // tets on the edge vanish
  mesh.vertex_ball(keep, ball);
  for (index_t t : ball)
    if (mesh.local_index(t, remove) < 0) add(mesh.tet(t));
  return q;
}

}  // namespace femorph
