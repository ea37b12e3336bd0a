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
  // Boundary faces, then their half-edges keyed by (min, max) vertex.
  std::vector<index_t> faces;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f)
      if (mesh.is_boundary_face(t, f)) faces.push_back(4 * t + f);
  }
  struct HalfEdge {
    std::uint64_t key;
    index_t corner_a, corner_b;  // corners (3 * face + k) at the key's two vertices
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * faces.size());
  auto vertex_of = [&](std::size_t face, int k) {
    const index_t code = faces[face];
    return mesh.tet(code >> 2)[kTetFace[code & 3][k]];
  };
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int l = (k + 1) % 3;
      index_t a = vertex_of(i, k), b = vertex_of(i, l);
      index_t ca = static_cast<index_t>(3 * i + k), cb = static_cast<index_t>(3 * i + l);
      if (a > b) {
        std::swap(a, b);
        std::swap(ca, cb);
      }
      edges.push_back({(static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b), ca, cb});
    }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });

  std::vector<index_t> parent(3 * faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t nbad = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i != 2) {
      ++nbad;
    } else {
      // The two faces meet along this edge: their corners at each endpoint
      // belong to the same fan.
      parent[find(edges[i].corner_a)] = find(edges[i + 1].corner_a);
      parent[find(edges[i].corner_b)] = find(edges[i + 1].corner_b);
    }
    i = j;
  }
  *bad_edges = nbad;

  std::vector<std::pair<index_t, index_t>> vertex_fan;
  vertex_fan.reserve(parent.size());
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) vertex_fan.emplace_back(vertex_of(i, k), find(static_cast<index_t>(3 * i + k)));
  std::sort(vertex_fan.begin(), vertex_fan.end());
  vertex_fan.erase(std::unique(vertex_fan.begin(), vertex_fan.end()), vertex_fan.end());
  std::size_t nfans = 0;
  for (std::size_t i = 1; i < vertex_fan.size(); ++i)
    if (vertex_fan[i].first == vertex_fan[i - 1].first &&
        (i < 2 || vertex_fan[i - 2].first != vertex_fan[i].first))
      ++nfans;  // count each vertex once
  *bad_fans = nfans;
}

}  // namespace internal
}  // namespace femorph
