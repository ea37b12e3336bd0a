#include "mesh/tet_mesh_internal.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace femorph {
namespace internal {

std::vector<FaceSlot>& face_slot_scratch() {
  thread_local std::vector<FaceSlot> slots;
  return slots;
}

index_t boundary_face_across_edge(const TetMesh& mesh, index_t t, int f, index_t v, index_t w) {
  index_t cur = t;
  int entered = f;
  for (;;) {
    const Tet& T = mesh.tet(cur);
    // The two faces of cur that contain v and w are opposite its other two
    // vertices; leave through the one we did not enter by.
    int exit = -1;
    for (int k = 0; k < 4; ++k)
      if (T[k] != v && T[k] != w && k != entered) {
        exit = k;
        break;
      }
    const index_t code = mesh.adjacency(cur, exit);
    if (code < 0) return 4 * cur + exit;
    cur = code >> 2;
    entered = code & 3;
  }
}

void boundary_manifold_counts(const TetMesh& mesh, std::size_t* bad_edges, std::size_t* bad_fans) {
  // Boundary faces, then their half-edges in buckets by their smaller
  // vertex (a counting sort: linear, where one sort of all half-edges is
  // not); the corners of each vertex in buckets the same way.
  std::vector<index_t> faces;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f)
      if (mesh.is_boundary_face(t, f)) faces.push_back(4 * t + f);
  }
  const std::size_t nv = static_cast<std::size_t>(mesh.vertex_slots());
  const std::size_t ncorners = 3 * faces.size();
  std::vector<index_t> corner_vertex(ncorners);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const index_t code = faces[i];
    const Tet& T = mesh.tet(code >> 2);
    for (int k = 0; k < 3; ++k) corner_vertex[3 * i + static_cast<std::size_t>(k)] = T[kTetFace[code & 3][k]];
  }
  struct HalfEdge {
    index_t other;               // the larger vertex (the bucket is the smaller)
    index_t corner_a, corner_b;  // corners (3 * face + k) at the smaller and the larger vertex
  };
  std::vector<index_t> edge_start(nv + 1, 0), corner_start(nv + 1, 0);
  for (std::size_t c = 0; c < ncorners; ++c) {
    const std::size_t l = c - c % 3 + (c % 3 + 1) % 3;  // the corner after c in its face
    ++edge_start[static_cast<std::size_t>(std::min(corner_vertex[c], corner_vertex[l])) + 1];
    ++corner_start[static_cast<std::size_t>(corner_vertex[c]) + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) {
    edge_start[v + 1] += edge_start[v];
    corner_start[v + 1] += corner_start[v];
  }
  std::vector<HalfEdge> edges(ncorners);
  std::vector<index_t> corners(ncorners);
  {
    std::vector<index_t> edge_fill(edge_start.begin(), edge_start.end() - 1);
    std::vector<index_t> corner_fill(corner_start.begin(), corner_start.end() - 1);
    for (std::size_t c = 0; c < ncorners; ++c) {
      const std::size_t l = c - c % 3 + (c % 3 + 1) % 3;
      index_t a = corner_vertex[c], b = corner_vertex[l];
      index_t ca = static_cast<index_t>(c), cb = static_cast<index_t>(l);
      if (a > b) {
        std::swap(a, b);
        std::swap(ca, cb);
      }
      edges[static_cast<std::size_t>(edge_fill[static_cast<std::size_t>(a)]++)] = {b, ca, cb};
      corners[static_cast<std::size_t>(corner_fill[static_cast<std::size_t>(corner_vertex[c])]++)] =
          static_cast<index_t>(c);
    }
  }

  std::vector<index_t> parent(ncorners);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t nbad = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    HalfEdge* first = edges.data() + edge_start[v];
    HalfEdge* last = edges.data() + edge_start[v + 1];
    std::sort(first, last, [](const HalfEdge& x, const HalfEdge& y) { return x.other < y.other; });
    for (HalfEdge* i = first; i < last;) {
      HalfEdge* j = i + 1;
      while (j < last && j->other == i->other) ++j;
      if (j - i != 2) {
        ++nbad;
      } else {
        // The two faces meet along this edge: their corners at each endpoint
        // belong to the same fan.
        parent[find(i[0].corner_a)] = find(i[1].corner_a);
        parent[find(i[0].corner_b)] = find(i[1].corner_b);
      }
      i = j;
    }
  }
  *bad_edges = nbad;

  // A vertex whose corners lie in more than one fan.
  std::size_t nfans = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t begin = static_cast<std::size_t>(corner_start[v]), end = static_cast<std::size_t>(corner_start[v + 1]);
    if (begin == end) continue;
    const index_t root = find(corners[begin]);
    bool several = false;
    for (std::size_t i = begin + 1; i < end && !several; ++i) several = find(corners[i]) != root;
    nfans += several;
  }
  *bad_fans = nfans;
}

}  // namespace internal
}  // namespace femorph
