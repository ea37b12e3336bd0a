// Vertex classes of thesis Fig. 2.37 (inner, surface, curve, corner) from the
// regions of the boundary faces around each vertex, and the curve-edge test
// they rest on: a boundary edge whose two boundary faces differ in region.
#include "mesh/tet_mesh.h"
#include "common/parallel.h"

#include "mesh/tet_mesh_internal.h"

#include <vector>

namespace femorph {

bool TetMesh::is_curve_edge(index_t a, index_t b, index_t hint) const {
  bool boundary = false;
  thread_local std::vector<index_t> ring, c;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary, hint) || !boundary) return false;
  return open_ring_on_curve(ring, c);
}

bool TetMesh::open_ring_on_curve(const std::vector<index_t>& ring, const std::vector<index_t>& c) const {
  // An open ring starts with the boundary face opposite c[1] in ring[0] and
  // ends with the one opposite c[n - 1] in ring[n - 1] (c has n + 1 entries).
  const index_t first = ring.front(), last = ring.back();
  return face_region(first, local_index(first, c[1])) != face_region(last, local_index(last, c[c.size() - 2]));
}

VertexClass TetMesh::classify_ball(index_t v, const std::vector<index_t>& ball) const {
  // Regions of the boundary faces around v, and the curve edges at v.
  index_t region0 = kInvalidIndex - 1;  // "none seen yet"
  bool on_bnd = false, several_regions = false;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    for (int f = 0; f < 4; ++f) {
      if (T[f] == v || rec_[t].n[f] >= 0) continue;
      const index_t r = face_region(t, f);
      if (!on_bnd) {
        on_bnd = true;
        region0 = r;
      } else if (r != region0) {
        several_regions = true;
      }
    }
  }
  if (!on_bnd) return VertexClass::Inner;
  if (!several_regions) return VertexClass::Surface;
  // Count curve edges: boundary edges (v, w) whose two faces differ in region.
  int curve_edges = 0;
  for (index_t t : ball) {
    const Tet& T = rec_[t].v;
    for (int f = 0; f < 4; ++f) {
      if (T[f] == v || rec_[t].n[f] >= 0) continue;
      // Boundary face f of t contains v; its two edges at v go to the other
      // two face vertices. Each boundary edge is seen from its two faces:
      // count it from the face with the smaller code to avoid doubles.
      const index_t r = face_region(t, f);
      for (int k = 0; k < 3; ++k) {
        const index_t w = T[kTetFace[f][k]];
        if (w == v) continue;
        const int other = internal::boundary_face_across_edge(*this, t, f, v, w);
        const index_t ot = other >> 2, of = other & 3;
        if (face_region(ot, of) != r && 4 * t + f < other) ++curve_edges;
      }
    }
  }
  return curve_edges == 2 ? VertexClass::Curve : VertexClass::Corner;
}

void TetMesh::classify_vertices() {
  const index_t n = vertex_slots();
  std::vector<WalkMarks> marks(static_cast<std::size_t>(parallel_threads()));
  std::vector<std::vector<index_t>> balls(marks.size());
  parallel_for_worker(
      n,
      [&](long i, int worker) {
        const index_t v = static_cast<index_t>(i);
        if (!vertex_alive(v)) {
          vclass_[v] = VertexClass::Inner;
          return;
        }
        std::vector<index_t>& ball = balls[static_cast<std::size_t>(worker)];
        vertex_ball(v, ball, marks[static_cast<std::size_t>(worker)]);
        vclass_[v] = classify_ball(v, ball);
      },
      kParallelMinItems, 4096);
}

}  // namespace femorph
