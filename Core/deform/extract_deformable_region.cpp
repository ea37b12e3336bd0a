// Deformable region extraction (thesis 2.5.3): the tets the deformation
// may change, so that repositioning and improvement stay local. The thesis
// sweeps or offsets the moved regions until they meet fixed vertices; here
// the same space is taken by distances along the mesh's edges: a vertex
// belongs when it is nearer to a moved (control or following) region than
// to every fixed region, or within `reach` of a moved region. The tets of
// those vertices and one layer of neighbours form the region, expanded
// further while it has few inner vertices (2.5.3.4, last paragraph).
#include "deform/deform.h"

#include "mesh/tet_mesh.h"
#include "mesh/unique_edges.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

namespace femorph {

namespace {

/// Shortest edge-path length from the flagged vertices to every vertex.
std::vector<double> edge_distance(const TetMesh& mesh, const std::vector<index_t>& offsets,
                                  const std::vector<index_t>& adjacent, const std::vector<std::uint8_t>& source) {
  const index_t nv = mesh.vertex_slots();
  std::vector<double> d(nv, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, index_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (index_t v = 0; v < nv; ++v) {
    if (source[v]) {
      d[v] = 0;
      queue.emplace(0.0, v);
    }
  }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > d[v]) continue;
    for (index_t k = offsets[v]; k < offsets[v + 1]; ++k) {
      const index_t u = adjacent[k];
      const double du = dv + (mesh.point(u) - mesh.point(v)).norm();
      if (du < d[u]) {
        d[u] = du;
        queue.emplace(du, u);
      }
    }
  }
  return d;
}

}  // namespace

std::vector<std::uint8_t> extract_deformable_region(const TetMesh& mesh, const DeformPlan& plan, double reach) {
  const index_t nt = mesh.tet_slots(), nv = mesh.vertex_slots();
  std::vector<std::uint8_t> moved(nv, 0), fixed(nv, 0);
  for (index_t t = 0; t < nt; ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      if (!mesh.is_boundary_face(t, f)) continue;
      const index_t r = mesh.face_region(t, f);
      const RegionRole role =
          r >= 0 && r < static_cast<index_t>(plan.roles.size()) ? plan.roles[r] : RegionRole::Fixed;
      std::vector<std::uint8_t>* flag = role == RegionRole::Fixed ? &fixed
                                        : role == RegionRole::Deformed ? nullptr
                                                                       : &moved;
      if (!flag) continue;
      for (int k = 0; k < 3; ++k) (*flag)[mesh.tet(t)[kTetFace[f][k]]] = 1;
    }
  }
  // Vertex adjacency (CSR) from the edges.
  const std::vector<Edge> edges = unique_edges(mesh);
  std::vector<index_t> offsets(nv + 1, 0), adjacent(2 * edges.size());
  for (const Edge& e : edges) {
    ++offsets[e.first + 1];
    ++offsets[e.second + 1];
  }
  for (index_t v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
  std::vector<index_t> fill(offsets.begin(), offsets.end() - 1);
  for (const Edge& e : edges) {
    adjacent[fill[e.first]++] = e.second;
    adjacent[fill[e.second]++] = e.first;
  }
  const std::vector<double> to_moved = edge_distance(mesh, offsets, adjacent, moved);
  const std::vector<double> to_fixed = edge_distance(mesh, offsets, adjacent, fixed);
  std::vector<std::uint8_t> near(nv, 0);
  for (index_t v = 0; v < nv; ++v) {
    near[v] = mesh.vertex_alive(v) && !fixed[v] && (to_moved[v] <= reach || to_moved[v] < to_fixed[v]);
  }
  std::vector<std::uint8_t> region(nt, 0);
  for (index_t t = 0; t < nt; ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (const index_t v : mesh.tet(t)) region[t] |= near[v];
  }
  // One layer of neighbours, more while few inner vertices can move.
  for (int layer = 0; layer < 8; ++layer) {
    std::vector<std::uint8_t> touched(nv, 0);
    for (index_t t = 0; t < nt; ++t) {
      if (region[t]) {
        for (const index_t v : mesh.tet(t)) touched[v] = 1;
      }
    }
    for (index_t t = 0; t < nt; ++t) {
      if (!mesh.tet_alive(t) || region[t]) continue;
      for (const index_t v : mesh.tet(t)) region[t] |= touched[v];
    }
    // Inner vertices whose whole ball is in the region.
    std::vector<std::uint8_t> free(nv, 1);
    for (index_t t = 0; t < nt; ++t) {
      if (mesh.tet_alive(t) && !region[t]) {
        for (const index_t v : mesh.tet(t)) free[v] = 0;
      }
    }
    std::size_t inner = 0;
    for (index_t v = 0; v < nv; ++v) inner += mesh.vertex_alive(v) && free[v] && !mesh.on_boundary(v);
    if (inner >= 20) break;
  }
  return region;
}

}  // namespace femorph
