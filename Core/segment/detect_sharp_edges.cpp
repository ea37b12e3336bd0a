#include "segment/detect_sharp_edges.h"
#include "common/parallel.h"

#include <cmath>

namespace femorph {

// Thesis 2.4.2 (A11): thresholding of the dihedral angle. An edge of a
// degenerate triangle (zero normal) is not sharp: it carries no direction.
SharpEdges detect_sharp_edges(const SurfaceMesh& surface, double angle) {
  const index_t nf = surface.num_triangles();
  const double cos_angle = std::cos(angle);
  SharpEdges out;
  out.edge.assign(static_cast<std::size_t>(nf) * 3, 0);
  out.vertex_degree.assign(surface.points.size(), 0);

  parallel_for_chunks(
      static_cast<long>(nf),
      [&](long begin, long end, int) {
        for (index_t f = static_cast<index_t>(begin); f < static_cast<index_t>(end); ++f) {
          const Vec3& n = surface.normals[f];
          const bool degenerate = n.squaredNorm() == 0;
          for (int k = 0; k < 3; ++k) {
            const index_t g = surface.neighbors[f][k];
            char sharp;
            if (g < 0) {
              sharp = 1;  // open edge
            } else {
              const Vec3& m = surface.normals[g];
              sharp = !degenerate && m.squaredNorm() != 0 && n.dot(m) < cos_angle;
            }
            out.edge[3 * static_cast<std::size_t>(f) + k] = sharp;
          }
        }
      },
      kParallelMinItems);

  // Each edge once: from its lower triangle (or its only one).
  for (index_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = surface.neighbors[f][k];
      if (!out.edge[3 * static_cast<std::size_t>(f) + k] || (g >= 0 && g < f)) continue;
      ++out.vertex_degree[surface.triangles[f][k]];
      ++out.vertex_degree[surface.triangles[f][(k + 1) % 3]];
    }
  return out;
}

}  // namespace femorph
