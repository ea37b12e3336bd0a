// A space mesh around given object meshes, for Adapt's input (thesis 3.7
// builds its inputs with an octree mesher; this uses TetGen, which 3.5.5
// also uses). The objects' surfaces are constraints that TetGen may not
// split (-Y): the space mesh is conformal to the objects' own meshes.
#include "adapt/adapt.h"

#include "adapt/tetgen_plc.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace femorph {

namespace {

using Key = std::array<index_t, 3>;

Key sorted(index_t a, index_t b, index_t c) {
  Key k{{a, b, c}};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

Status mesh_space_around(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                         const std::vector<int>& material, const Vec3& lo, const Vec3& hi, double edge,
                         std::vector<Vec3>& out_points, std::vector<Tet>& out_tets, std::vector<int>& out_material) {
  if (tets.empty() || material.size() != tets.size()) return Status::failure("mesh_space_around: no objects");
  // The objects' surface: faces of one tet (kTetFace order: outward), and
  // face-connected components (one hole point each).
  std::map<Key, std::pair<int, index_t>> faces;  // -> (count, tet)
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      auto& e = faces[sorted(tets[t][kTetFace[f][0]], tets[t][kTetFace[f][1]], tets[t][kTetFace[f][2]])];
      ++e.first;
      e.second = static_cast<index_t>(t);
    }
  std::vector<index_t> parent(tets.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](index_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::map<Key, index_t> first_tet;
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const Key k = sorted(tets[t][kTetFace[f][0]], tets[t][kTetFace[f][1]], tets[t][kTetFace[f][2]]);
      const auto it = first_tet.find(k);
      if (it == first_tet.end()) first_tet.emplace(k, static_cast<index_t>(t));
      else parent[find(static_cast<index_t>(t))] = find(it->second);
    }
  std::vector<Vec3> holes;
  for (std::size_t t = 0; t < tets.size(); ++t)
    if (find(static_cast<index_t>(t)) == static_cast<index_t>(t)) {
      const Tet& T = tets[t];
      holes.push_back(0.25 * (points[T[0]] + points[T[1]] + points[T[2]] + points[T[3]]));
    }
  std::vector<Key> surface;
  std::vector<index_t> surface_point(points.size(), kInvalidIndex);
  std::vector<Vec3> pts;
  double edge_sum = 0;
  std::size_t edge_count = 0;
  for (const auto& [k, e] : faces) {
    if (e.first != 1) continue;
    for (const index_t v : k)
      if (surface_point[v] < 0) {
        surface_point[v] = static_cast<index_t>(pts.size());
        pts.push_back(points[v]);
      }
    surface.push_back({surface_point[k[0]], surface_point[k[1]], surface_point[k[2]]});
    for (int i = 0; i < 3; ++i) edge_sum += (points[k[i]] - points[k[(i + 1) % 3]]).norm();
    edge_count += 3;
  }
  for (const Vec3& p : pts)
    if ((p.array() <= lo.array()).any() || (p.array() >= hi.array()).any())
      return Status::failure("mesh_space_around: the objects reach the box; make it larger");
  if (edge <= 0) edge = 4 * edge_sum / static_cast<double>(edge_count);
  // The box's faces cut into squares of about `edge`, two triangles each.
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, static_cast<int>(std::round((hi[a] - lo[a]) / edge)));
  std::map<std::array<int, 3>, index_t> lattice;
  const auto box_point = [&](std::array<int, 3> g) {
    const auto it = lattice.find(g);
    if (it != lattice.end()) return it->second;
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = g[a] == n[a] ? hi[a] : lo[a] + (hi[a] - lo[a]) * g[a] / n[a];
    const index_t id = static_cast<index_t>(pts.size());
    pts.push_back(p);
    lattice.emplace(g, id);
    return id;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n[b]; ++i)
        for (int j = 0; j < n[c]; ++j) {
          index_t q[4];
          for (int r = 0; r < 4; ++r) {
            std::array<int, 3> g;
            g[a] = side ? n[a] : 0;
            g[b] = i + (r == 1 || r == 2);
            g[c] = j + (r >= 2);
            q[r] = box_point(g);
          }
          surface.push_back({q[0], q[1], q[2]});
          surface.push_back({q[0], q[2], q[3]});
        }
  }

  // p: a piecewise linear complex; Y: no Steiner point on it; q: radius-edge
  // ratio bound (the sizes grade from the objects' surfaces to the box's);
  // Q: quiet.
  std::vector<Vec3> tg_points;
  std::vector<Tet> tg_tets;
  const Status s = internal::tetgen_plc(pts, surface, holes, "pYq1.4Q", tg_points, tg_tets);
  if (!s) return Status::failure("mesh_space_around: " + s.message + " (self-intersecting or touching object surfaces?)");
  // Output points: the objects' as given, then TetGen's others (its first
  // points are the input's, in order).
  out_points = points;
  out_tets = tets;
  out_material = material;
  std::vector<index_t> id(tg_points.size(), kInvalidIndex);
  for (std::size_t v = 0; v < points.size(); ++v)
    if (surface_point[v] >= 0) id[surface_point[v]] = static_cast<index_t>(v);
  for (std::size_t i = 0; i < tg_points.size(); ++i)
    if (id[i] < 0) {
      id[i] = static_cast<index_t>(out_points.size());
      out_points.push_back(tg_points[i]);
    }
  for (const Tet& t : tg_tets) {
    out_tets.push_back({{id[t[0]], id[t[1]], id[t[2]], id[t[3]]}});
    out_material.push_back(0);
  }
  // Box points TetGen did not use would dangle: it uses them all (-Y).
  return Status::success();
}

}  // namespace femorph
