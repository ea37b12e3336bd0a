// Deformable region extraction (thesis 2.5.3): the tets the deformation
// may change, so that repositioning and improvement stay local. Here the
// region is every tet with a vertex within `reach` of a vertex of a moved
// (control or following) region, plus one layer of neighbours, expanded
// further while it has few inner vertices (2.5.3.4, last paragraph).
#include "deform/deform.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace femorph {

namespace {
struct CellKey {
  long long x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
}  // namespace

std::vector<std::uint8_t> extract_deformable_region(const TetMesh& mesh, const DeformPlan& plan, double reach) {
  const index_t nt = mesh.tet_slots(), nv = mesh.vertex_slots();
  std::vector<std::uint8_t> seed(nv, 0);
  for (index_t t = 0; t < nt; ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t r = mesh.face_region(t, f);
      if (r < 0 || r >= static_cast<index_t>(plan.roles.size())) continue;
      if (plan.roles[r] != RegionRole::Control && plan.roles[r] != RegionRole::Following) continue;
      for (int k = 0; k < 3; ++k) seed[mesh.tet(t)[kTetFace[f][k]]] = 1;
    }
  }
  // Vertices within reach of a seed, by a hash grid of cell `reach`.
  const double h = std::max(reach, 1e-12 * plan.part_size);
  std::unordered_map<CellKey, std::vector<index_t>, CellHash> grid;
  const auto key = [&](const Vec3& p) {
    return CellKey{static_cast<long long>(std::floor(p.x() / h)), static_cast<long long>(std::floor(p.y() / h)),
                   static_cast<long long>(std::floor(p.z() / h))};
  };
  for (index_t v = 0; v < nv; ++v) {
    if (seed[v] && mesh.vertex_alive(v)) grid[key(mesh.point(v))].push_back(v);
  }
  std::vector<std::uint8_t> near(nv, 0);
  const double reach2 = reach * reach;
  for (index_t v = 0; v < nv; ++v) {
    if (!mesh.vertex_alive(v)) continue;
    if (seed[v]) {
      near[v] = 1;
      continue;
    }
    const Vec3& p = mesh.point(v);
    const CellKey c = key(p);
    for (long long dx = -1; dx <= 1 && !near[v]; ++dx) {
      for (long long dy = -1; dy <= 1 && !near[v]; ++dy) {
        for (long long dz = -1; dz <= 1 && !near[v]; ++dz) {
          const auto it = grid.find(CellKey{c.x + dx, c.y + dy, c.z + dz});
          if (it == grid.end()) continue;
          for (const index_t s : it->second) {
            if ((mesh.point(s) - p).squaredNorm() <= reach2) {
              near[v] = 1;
              break;
            }
          }
        }
      }
    }
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
