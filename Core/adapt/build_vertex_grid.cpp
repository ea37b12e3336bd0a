// G_v, the vertex search grid of thesis 3.4.1: fixed in space, each cell
// holds the vertices inside it. Rebuilt per step by a counting sort (one
// pass over the vertices), which costs less than keeping it up to date.
#include "adapt/adapt.h"

#include <algorithm>
#include <cmath>

namespace femorph {

VertexGrid build_vertex_grid(const TetMesh& mesh, const Vec3& lo, const Vec3& hi, double h) {
  VertexGrid g;
  g.h = h;
  g.origin = lo - Vec3::Constant(0.5 * h);
  for (int a = 0; a < 3; ++a)
    g.n[a] = std::max(1, static_cast<int>(std::ceil((hi[a] - g.origin[a]) / h + 0.5)));
  const std::size_t cells = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  g.start.assign(cells + 1, 0);
  const index_t nv = mesh.vertex_slots();
  std::vector<index_t> cell_of(static_cast<std::size_t>(nv), -1);
  for (index_t v = 0; v < nv; ++v) {
    if (!mesh.vertex_alive(v)) continue;
    const Vec3 q = (mesh.point(v) - g.origin) / h;
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(q[a])), 0, g.n[a] - 1);
    cell_of[v] = static_cast<index_t>(g.cell_id(c[0], c[1], c[2]));
    ++g.start[static_cast<std::size_t>(cell_of[v]) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  g.vertices.resize(static_cast<std::size_t>(g.start[cells]));
  std::vector<index_t> fill(g.start.begin(), g.start.end() - 1);
  for (index_t v = 0; v < nv; ++v)
    if (cell_of[v] >= 0) g.vertices[static_cast<std::size_t>(fill[cell_of[v]]++)] = v;
  return g;
}

}  // namespace femorph
