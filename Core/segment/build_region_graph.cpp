// Region adjacency with G0/G1 continuity, and convexity: the surface
// information of thesis 2.5.1.1.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace femorph {
namespace segment {

namespace {

/// +1 when the region's triangles face along the fitted surface's normal
/// (away from the axis / centre / core circle), -1 when against it.
double facing(const State& st, const Region& region, const std::vector<index_t>& triangles) {
  double sum = 0;
  for (index_t f : triangles) {
    const Tri& t = st.surface.triangles[f];
    const Vec3 c = (st.surface.points[t[0]] + st.surface.points[t[1]] + st.surface.points[t[2]]) / 3.0;
    sum += st.surface.areas[f] * st.surface.normals[f].dot(surface_normal(region.surface, c));
  }
  return sum >= 0 ? 1.0 : -1.0;
}

}  // namespace

void build_region_graph(const State& st, Segmentation& out) {
  const SurfaceMesh& s = st.surface;
  const index_t nr = static_cast<index_t>(out.regions.size());
  std::vector<std::vector<index_t>> triangles(static_cast<std::size_t>(nr));
  for (index_t f = 0; f < s.num_triangles(); ++f) triangles[out.triangle_region[f]].push_back(f);
  std::vector<double> sign(static_cast<std::size_t>(nr), 1.0);
  for (index_t r = 0; r < nr; ++r) {
    Region& region = out.regions[r];
    if (region.type == SurfaceType::Unknown) continue;
    sign[r] = facing(st, region, triangles[r]);
    if (region.type != SurfaceType::Plane)
      region.convexity = sign[r] > 0 ? Convexity::Convex : Convexity::Concave;
  }
  // Oriented normal of region r at a point: the fitted surface's, or for an
  // unknown region the mean of its triangles' normals at vertex v.
  auto normal_at = [&](index_t r, index_t v) -> Vec3 {
    const Region& region = out.regions[r];
    if (region.type != SurfaceType::Unknown) return sign[r] * surface_normal(region.surface, s.points[v]);
    Vec3 n = Vec3::Zero();
    for (index_t i = s.vertex_offsets[v]; i < s.vertex_offsets[v + 1]; ++i) {
      const index_t f = s.vertex_triangles[i];
      if (out.triangle_region[f] == r) n += s.areas[f] * s.normals[f];
    }
    return n.normalized();
  };
  // Shared edges per region pair, then G1 when the two surfaces' normals
  // agree at every vertex of the shared boundary.
  const double cos_g1 = std::cos(degrees_to_radians(2.0));
  std::map<std::pair<index_t, index_t>, bool> tangent;  // (a < b) -> G1 so far
  for (index_t f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g < 0) continue;
      index_t a = out.triangle_region[f], b = out.triangle_region[g];
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      bool& g1 = tangent.emplace(std::make_pair(a, b), true).first->second;
      if (!g1) continue;
      for (index_t v : {s.triangles[f][k], s.triangles[f][(k + 1) % 3]})
        if (normal_at(a, v).dot(normal_at(b, v)) < cos_g1) g1 = false;
    }
  for (const auto& [pair, g1] : tangent) {
    const Continuity c = g1 ? Continuity::G1 : Continuity::G0;
    out.regions[pair.first].neighbors.push_back(pair.second);
    out.regions[pair.first].continuity.push_back(c);
    out.regions[pair.second].neighbors.push_back(pair.first);
    out.regions[pair.second].continuity.push_back(c);
  }
  // neighbors ascending (the map visits pairs in order; sort the second role).
  for (Region& region : out.regions) {
    std::vector<std::size_t> order(region.neighbors.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return region.neighbors[x] < region.neighbors[y]; });
    std::vector<index_t> n;
    std::vector<Continuity> c;
    for (std::size_t i : order) {
      n.push_back(region.neighbors[i]);
      c.push_back(region.continuity[i]);
    }
    region.neighbors.swap(n);
    region.continuity.swap(c);
  }
}

}  // namespace segment
}  // namespace femorph
