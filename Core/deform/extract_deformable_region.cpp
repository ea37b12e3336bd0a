// Deformable region extraction (thesis 2.5.3): the tets the deformation
// may change, so that repositioning and improvement stay local. The thesis
// sweeps or offsets the moved regions until they meet fixed vertices; here
// the same space is taken by distances along the mesh's edges: a vertex
// belongs when it is nearer to a moved (control or following) region than
// to every fixed region, or within `reach` of a moved region. The tets of
// those vertices and one layer of neighbours form the region, expanded
// further while it has few inner vertices (2.5.3.4, last paragraph).
#include "deform/deform.h"

#include "common/parallel.h"
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>

namespace femorph {

namespace {

/// Vertex adjacency (CSR, neighbours unsorted) from the tets around each
/// vertex: each vertex's tets gathered by a counting sort, their other
/// vertices taken once.
struct VertexNeighbors {
  std::vector<index_t> offsets, adjacent;

  explicit VertexNeighbors(const TetMesh& mesh) {
    const index_t nt = mesh.tet_slots(), nv = mesh.vertex_slots();
    std::vector<index_t> tet_offsets(static_cast<std::size_t>(nv) + 1, 0);
    for (index_t t = 0; t < nt; ++t) {
      if (!mesh.tet_alive(t)) continue;
      for (const index_t v : mesh.tet(t)) ++tet_offsets[v + 1];
    }
    for (index_t v = 0; v < nv; ++v) tet_offsets[v + 1] += tet_offsets[v];
    std::vector<index_t> tets(tet_offsets[nv]), fill(tet_offsets.begin(), tet_offsets.end() - 1);
    for (index_t t = 0; t < nt; ++t) {
      if (!mesh.tet_alive(t)) continue;
      for (const index_t v : mesh.tet(t)) tets[fill[v]++] = t;
    }
    // At most 3 neighbours per incident tet: gathered into those slots, then
    // compacted.
    std::vector<index_t> slots(3 * static_cast<std::size_t>(tet_offsets[nv])), count(nv, 0);
    std::vector<std::vector<index_t>> stamp(static_cast<std::size_t>(parallel_threads()));
    parallel_for_chunks(
        nv,
        [&](long begin, long end, int worker) {
          std::vector<index_t>& seen = stamp[static_cast<std::size_t>(worker)];
          if (seen.empty()) seen.assign(nv, kInvalidIndex);
          for (long v = begin; v < end; ++v) {
            index_t* out = slots.data() + 3 * static_cast<std::size_t>(tet_offsets[v]);
            index_t n = 0;
            seen[v] = static_cast<index_t>(v);
            for (index_t k = tet_offsets[v]; k < tet_offsets[v + 1]; ++k) {
              for (const index_t u : mesh.tet(tets[k])) {
                if (seen[u] == v) continue;
                seen[u] = static_cast<index_t>(v);
                out[n++] = u;
              }
            }
            count[v] = n;
          }
        },
        4096);
    offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
    for (index_t v = 0; v < nv; ++v) offsets[v + 1] = offsets[v] + count[v];
    adjacent.resize(offsets[nv]);
    for (index_t v = 0; v < nv; ++v)
      std::copy_n(slots.data() + 3 * static_cast<std::size_t>(tet_offsets[v]), count[v], adjacent.data() + offsets[v]);
  }

  /// f(u) for each neighbour u of v.
  template <class F>
  void for_each(index_t v, F&& f) const {
    for (index_t k = offsets[v]; k < offsets[v + 1]; ++k) f(adjacent[k]);
  }
};

/// Per vertex, whether its nearest flagged vertex along the edges is a moved
/// one (strictly nearer than every fixed one): one Dijkstra from both sets,
/// each vertex taking the label of its nearest source, fixed on a tie. It
/// stops when no moved-labelled vertex is left to settle: a vertex nearer to
/// the moved ones is reached through such vertices only.
std::vector<std::uint8_t> nearer_to_moved(const TetMesh& mesh, const VertexNeighbors& neighbors,
                                          const std::vector<std::uint8_t>& moved,
                                          const std::vector<std::uint8_t>& fixed) {
  const index_t nv = mesh.vertex_slots();
  std::vector<double> d(nv, std::numeric_limits<double>::infinity());
  std::vector<std::uint8_t> label(nv, 0), done(nv, 0);  // label 0 fixed, 1 moved
  using Item = std::tuple<double, std::uint8_t, index_t>;  // distance, label, vertex
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  std::size_t moved_queued = 0;
  for (index_t v = 0; v < nv; ++v) {
    if (fixed[v] || moved[v]) {
      d[v] = 0;
      label[v] = fixed[v] ? 0 : 1;
      queue.emplace(0.0, label[v], v);
      moved_queued += label[v];
    }
  }
  while (moved_queued > 0) {
    const auto [dv, lv, v] = queue.top();
    queue.pop();
    moved_queued -= lv;
    if (done[v]) continue;
    done[v] = 1;
    const Vec3& x = mesh.point(v);
    neighbors.for_each(v, [&](index_t u) {
      if (done[u]) return;
      const double du = dv + (mesh.point(u) - x).norm();
      if (du < d[u] || (du == d[u] && lv < label[u])) {
        d[u] = du;
        label[u] = lv;
        queue.emplace(du, lv, u);
        moved_queued += lv;
      }
    });
  }
  return label;
}

/// The vertices within `reach` of the moved vertices along the edges (a
/// Dijkstra that stops at `reach`, so it stays local).
std::vector<std::uint8_t> within_reach(const TetMesh& mesh, const VertexNeighbors& neighbors,
                                       const std::vector<std::uint8_t>& moved, double reach) {
  const index_t nv = mesh.vertex_slots();
  std::vector<double> d(nv, std::numeric_limits<double>::infinity());
  std::vector<std::uint8_t> in(nv, 0);
  using Item = std::pair<double, index_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (index_t v = 0; v < nv; ++v) {
    if (moved[v]) {
      d[v] = 0;
      queue.emplace(0.0, v);
    }
  }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > reach) break;
    if (in[v]) continue;
    in[v] = 1;
    const Vec3& x = mesh.point(v);
    neighbors.for_each(v, [&](index_t u) {
      const double du = dv + (mesh.point(u) - x).norm();
      if (du < d[u] && du <= reach) {
        d[u] = du;
        queue.emplace(du, u);
      }
    });
  }
  return in;
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
  VertexNeighbors neighbors(mesh);
  const std::vector<std::uint8_t> nearer = nearer_to_moved(mesh, neighbors, moved, fixed);
  const std::vector<std::uint8_t> reached = within_reach(mesh, neighbors, moved, reach);
  std::vector<std::uint8_t> near(nv, 0);
  for (index_t v = 0; v < nv; ++v) near[v] = mesh.vertex_alive(v) && !fixed[v] && (reached[v] || nearer[v]);
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
