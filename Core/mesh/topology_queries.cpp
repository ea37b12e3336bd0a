// TetMesh's topology queries, all walks through face adjacency: the ball of
// a vertex (breadth-first from vertex_tet), its neighbours, a tet on an edge,
// the ring of tets around an edge in rotation order, a tet on a face.
#include "mesh/tet_mesh.h"

#include <algorithm>

namespace femorph {

void TetMesh::vertex_ball(index_t v, std::vector<index_t>& out) const {
  out.clear();
  if (vertex_tet_[v] < 0) return;
  const std::uint16_t mark = next_tet_mark();
  walk_ball(v, out, tet_marks_.stamp.data(), mark);
}

void TetMesh::vertex_ball(index_t v, std::vector<index_t>& out, WalkMarks& marks) const {
  out.clear();
  if (vertex_tet_[v] < 0) return;
  const std::uint16_t mark = marks.next(rec_.size());
  walk_ball(v, out, marks.stamp.data(), mark);
}

index_t TetMesh::walk_ball(index_t v, std::vector<index_t>& out, std::uint16_t* marks, std::uint16_t mark,
                           index_t stop_at) const {
  // Breadth-first over the faces that contain v (those opposite the other
  // three vertices), marking visited tets.
  const index_t t0 = vertex_tet_[v];
  out.push_back(t0);
  marks[t0] = mark;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const index_t t = out[i];
    const TetRecord& R = rec_[t];
    if (stop_at >= 0 && (R.v[0] == stop_at || R.v[1] == stop_at || R.v[2] == stop_at || R.v[3] == stop_at))
      return t;
    for (int f = 0; f < 4; ++f) {
      if (R.v[f] == v) continue;
      const index_t code = R.n[f];
      if (code < 0) continue;
      const index_t n = code >> 2;
      if (marks[n] != mark) {
        marks[n] = mark;
        out.push_back(n);
      }
    }
  }
  return kInvalidIndex;
}

void TetMesh::vertex_neighbors(index_t v, std::vector<index_t>& out) const {
  vertex_ball(v, scratch_verts_);
  out.clear();
  for (index_t t : scratch_verts_)
    for (index_t w : rec_[t].v)
      if (w != v) out.push_back(w);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool TetMesh::edge_tet_without_walk(index_t a, index_t b, index_t hint, index_t* t) const {
  *t = kInvalidIndex;
  if (!vertex_alive(a) || !vertex_alive(b) || a == b) return true;
  const index_t ta = vertex_tet_[a], tb = vertex_tet_[b];
  if (tet_alive(hint) && local_index(hint, a) >= 0 && local_index(hint, b) >= 0)
    *t = hint;
  else if (local_index(ta, b) >= 0)
    *t = ta;
  else if (local_index(tb, a) >= 0)
    *t = tb;
  return *t >= 0;
}

index_t TetMesh::find_edge_tet(index_t a, index_t b, index_t hint) const {
  index_t t;
  if (edge_tet_without_walk(a, b, hint, &t)) return t;
  scratch_verts_.clear();
  if (vertex_tet_[a] < 0) return kInvalidIndex;
  const std::uint16_t mark = next_tet_mark();  // may grow tet_marks_
  return walk_ball(a, scratch_verts_, tet_marks_.stamp.data(), mark, b);
}

index_t TetMesh::find_edge_tet(index_t a, index_t b, index_t hint, WalkMarks& marks) const {
  index_t t;
  if (edge_tet_without_walk(a, b, hint, &t)) return t;
  thread_local std::vector<index_t> ball;
  ball.clear();
  if (vertex_tet_[a] < 0) return kInvalidIndex;
  const std::uint16_t mark = marks.next(rec_.size());
  return walk_ball(a, ball, marks.stamp.data(), mark, b);
}

bool TetMesh::edge_ring(index_t a, index_t b, std::vector<index_t>& ring, bool* on_boundary, index_t hint) const {
  return edge_ring_with_vertices(a, b, ring, scratch_ring_, on_boundary, hint);
}

bool TetMesh::edge_ring_with_vertices(index_t a, index_t b, std::vector<index_t>& ring,
                                      std::vector<index_t>& opposite, bool* on_boundary, index_t hint) const {
  ring.clear();
  opposite.clear();
  const index_t t0 = find_edge_tet(a, b, hint);
  if (t0 < 0) return false;
  // In a tet containing a and b with other vertices (x, y), crossing the face
  // opposite x leads to the next tet, which contains y and a new vertex.
  auto others = [&](index_t t, index_t* x, index_t* y) {
    int k = 0;
    index_t o[2] = {kInvalidIndex, kInvalidIndex};
    for (index_t w : rec_[t].v)
      if (w != a && w != b) o[k++] = w;
    *x = o[0];
    *y = o[1];
  };
  // Walk backwards first (crossing the face opposite y) to find an end of an
  // open ring, so the forward walk below lists the whole ring in order.
  index_t start = t0, x, y;
  others(t0, &x, &y);
  index_t start_x = x;  // first opposite vertex of the forward walk
  bool closed = false;
  {
    index_t t = t0, cx = x, cy = y;
    for (;;) {
      const index_t code = rec_[t].n[local_index(t, cy)];
      if (code < 0) {  // boundary: t is the first tet of the open ring
        start = t;
        start_x = cx;
        break;
      }
      const index_t n = code >> 2;
      if (n == t0) {
        closed = true;
        break;
      }
      // n contains a, b, cx and a new vertex w; going backwards, cy := cx.
      index_t nx, ny;
      others(n, &nx, &ny);
      const index_t w = (nx == cx) ? ny : nx;
      cy = cx;
      cx = w;
      t = n;
    }
  }
  if (closed) {
    start = t0;
    start_x = x;
  }
  // Forward: ring[i] has opposite vertices c[i], c[i + 1].
  index_t t = start, cx = start_x;
  for (;;) {
    index_t ox, oy;
    others(t, &ox, &oy);
    const index_t cy = (ox == cx) ? oy : ox;
    ring.push_back(t);
    opposite.push_back(cx);
    const index_t code = rec_[t].n[local_index(t, cx)];
    if (code < 0) {
      opposite.push_back(cy);
      break;
    }
    const index_t n = code >> 2;
    if (n == start) break;
    cx = cy;
    t = n;
  }
  if (on_boundary) *on_boundary = !closed;
  return true;
}

index_t TetMesh::find_face(index_t a, index_t b, index_t c, int* local_face) const {
  if (!vertex_alive(a) || !vertex_alive(b) || !vertex_alive(c)) return kInvalidIndex;
  vertex_ball(a, scratch_verts_);
  for (index_t t : scratch_verts_) {
    const int ib = local_index(t, b), ic = local_index(t, c);
    if (ib < 0 || ic < 0) continue;
    const int ia = local_index(t, a);
    const int f = 6 - ia - ib - ic;  // the remaining local index
    if (local_face) *local_face = f;
    return t;
  }
  return kInvalidIndex;
}

}  // namespace femorph
