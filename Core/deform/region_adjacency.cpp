// Region graph for the classification of 2.5.2: which regions meet, and
// whether they meet with G1 continuity (fillets are tangent to their
// neighbours), from the mesh's boundary faces.
#include "deform/deform.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace femorph {

bool RegionGraph::adjacent(index_t a, index_t b) const {
  if (a < 0 || a >= static_cast<index_t>(neighbors.size())) return false;
  return std::binary_search(neighbors[a].begin(), neighbors[a].end(), b);
}

bool RegionGraph::tangent(index_t a, index_t b) const {
  if (a < 0 || a >= static_cast<index_t>(neighbors.size())) return false;
  const auto it = std::lower_bound(neighbors[a].begin(), neighbors[a].end(), b);
  return it != neighbors[a].end() && *it == b && g1[a][it - neighbors[a].begin()];
}

RegionGraph region_adjacency(const TetMesh& mesh, std::size_t region_count, double g1_angle_deg) {
  RegionGraph graph;
  graph.neighbors.assign(region_count, {});
  graph.g1.assign(region_count, {});
  graph.area.assign(region_count, 0.0);
  // The vertices on faces of two or more regions: only an edge between two
  // of them can part two regions.
  // fn(t, f, r) for each boundary face (t, f) of a region r.
  const auto for_each_region_face = [&](auto&& fn) {
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      for (int f = 0; f < 4; ++f) {
        if (!mesh.is_boundary_face(t, f)) continue;
        const index_t r = mesh.face_region(t, f);
        if (r >= 0 && r < static_cast<index_t>(region_count)) fn(t, f, r);
      }
    }
  };
  std::vector<index_t> first_region(static_cast<std::size_t>(mesh.vertex_slots()), kInvalidIndex);
  std::vector<std::uint8_t> shared(first_region.size(), 0);
  for_each_region_face([&](index_t t, int f, index_t r) {
    for (int k = 0; k < 3; ++k) {
      const index_t v = mesh.tet(t)[kTetFace[f][k]];
      if (first_region[v] == kInvalidIndex) first_region[v] = r;
      shared[v] |= first_region[v] != r;
    }
  });
  // Every such boundary edge once per face (its two ends, region and
  // normal), sorted so that the two faces of an edge are next to each other.
  struct Side {
    index_t a, b, region;
    Vec3 normal;
  };
  std::vector<Side> sides;
  for_each_region_face([&](index_t t, int f, index_t r) {
    const Tet& T = mesh.tet(t);
    const Vec3& a = mesh.point(T[kTetFace[f][0]]);
    const Vec3& b = mesh.point(T[kTetFace[f][1]]);
    const Vec3& c = mesh.point(T[kTetFace[f][2]]);
    const Vec3 n = (b - a).cross(c - a);
    graph.area[r] += 0.5 * n.norm();
    const Vec3 unit = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      index_t u = T[kTetFace[f][k]], v = T[kTetFace[f][(k + 1) % 3]];
      if (!shared[u] || !shared[v]) continue;
      if (u > v) std::swap(u, v);
      sides.push_back({u, v, r, unit});
    }
  });
  std::sort(sides.begin(), sides.end(),
            [](const Side& x, const Side& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  // Per region pair: summed angle and count.
  std::map<std::pair<index_t, index_t>, std::pair<double, int>> pairs;
  for (std::size_t i = 0; i + 1 < sides.size(); ++i) {
    const Side& x = sides[i];
    const Side& y = sides[i + 1];
    if (x.a != y.a || x.b != y.b) continue;
    const bool two = i + 2 >= sides.size() || sides[i + 2].a != x.a || sides[i + 2].b != x.b;
    if (!two || (i > 0 && sides[i - 1].a == x.a && sides[i - 1].b == x.b)) continue;  // non-manifold edge
    if (x.region == y.region) continue;
    index_t a = x.region, b = y.region;
    if (a > b) std::swap(a, b);
    const double c = std::clamp(x.normal.dot(y.normal), -1.0, 1.0);
    auto& p = pairs[{a, b}];
    p.first += std::acos(c);
    p.second += 1;
  }
  const double limit = degrees_to_radians(g1_angle_deg);
  for (const auto& entry : pairs) {
    const index_t a = entry.first.first, b = entry.first.second;
    const bool smooth = entry.second.first / entry.second.second < limit;
    graph.neighbors[a].push_back(b);
    graph.neighbors[b].push_back(a);
    graph.g1[a].push_back(smooth);
    graph.g1[b].push_back(smooth);
  }
  // Sort each neighbour list with its flags.
  for (std::size_t r = 0; r < region_count; ++r) {
    std::vector<std::pair<index_t, bool>> items;
    for (std::size_t k = 0; k < graph.neighbors[r].size(); ++k) items.emplace_back(graph.neighbors[r][k], graph.g1[r][k]);
    std::sort(items.begin(), items.end());
    for (std::size_t k = 0; k < items.size(); ++k) {
      graph.neighbors[r][k] = items[k].first;
      graph.g1[r][k] = items[k].second;
    }
  }
  return graph;
}

}  // namespace femorph
