// Boundary edge recognition, thesis 2.4.6 (A16): feature vertices (more than
// two boundary edges), boundary edge segments between them or closed loops,
// each classified and fitted (classify_boundary_curve).
#include "segment/segmentation_state.h"

#include <algorithm>

namespace femorph {
namespace segment {

void recognize_boundary_curves(const State& st, Segmentation& out) {
  const SurfaceMesh& s = st.surface;
  const index_t np = s.num_points();
  // Boundary edges between regions, as a vertex adjacency (each edge once).
  struct Edge {
    index_t a, b, region_a, region_b;
  };
  std::vector<Edge> edges;
  for (index_t f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g < 0 || g < f) continue;
      const index_t ra = out.triangle_region[f], rb = out.triangle_region[g];
      if (ra == rb) continue;
      edges.push_back({s.triangles[f][k], s.triangles[f][(k + 1) % 3], std::min(ra, rb), std::max(ra, rb)});
    }
  std::vector<index_t> offset(static_cast<std::size_t>(np) + 1, 0);
  for (const Edge& e : edges) {
    ++offset[e.a + 1];
    ++offset[e.b + 1];
  }
  for (index_t v = 0; v < np; ++v) offset[v + 1] += offset[v];
  std::vector<index_t> incident(offset.back()), fill(offset.begin(), offset.end() - 1);
  for (index_t e = 0; e < static_cast<index_t>(edges.size()); ++e) {
    incident[fill[edges[e].a]++] = e;
    incident[fill[edges[e].b]++] = e;
  }
  auto degree = [&](index_t v) { return offset[v + 1] - offset[v]; };
  // Thesis: a feature vertex has more than two boundary edges (and an open
  // end, impossible on a closed surface, would have one).
  auto is_feature = [&](index_t v) { return degree(v) != 2 && degree(v) > 0; };

  out.vertex_class.assign(static_cast<std::size_t>(np), 1);
  out.vertex_curve.assign(static_cast<std::size_t>(np), kInvalidIndex);
  std::vector<char> used(edges.size(), 0);
  auto other_end = [&](index_t e, index_t v) { return edges[e].a == v ? edges[e].b : edges[e].a; };

  auto emit = [&](std::vector<index_t> chain, bool closed, index_t first_edge) {
    BoundaryCurve curve;
    curve.id = static_cast<index_t>(out.curves.size());
    curve.closed = closed;
    curve.region_a = edges[first_edge].region_a;
    curve.region_b = edges[first_edge].region_b;
    std::vector<Vec3> points;
    for (index_t v : chain) points.push_back(s.points[v]);
    const CurveFit fit = classify_boundary_curve(points, closed, st.near_tolerance(), out.regions[curve.region_a].surface,
                                                 out.regions[curve.region_b].surface);
    curve.curve = fit.curve;
    curve.type = fit.ok ? fit.curve.type : CurveType::Unclassified;
    // Along a freeform (unknown) region only a straight line is certain: a
    // planar section of it may look like an arc within the tolerance.
    const bool freeform = out.regions[curve.region_a].type == SurfaceType::Unknown ||
                          out.regions[curve.region_b].type == SurfaceType::Unknown;
    if (freeform && curve.type != CurveType::Line) curve.type = curve.curve.type = CurveType::Unclassified;
    curve.fit_max = fit.max_abs;
    // G1 where the two regions meet tangentially (build_region_graph).
    const Region& ra = out.regions[curve.region_a];
    const auto it = std::find(ra.neighbors.begin(), ra.neighbors.end(), curve.region_b);
    if (it != ra.neighbors.end()) curve.continuity = ra.continuity[it - ra.neighbors.begin()];
    for (std::size_t i = 0; i < chain.size(); ++i) {
      const index_t v = chain[i];
      if (is_feature(v)) continue;  // corners belong to several curves
      out.vertex_class[v] = 2;
      out.vertex_curve[v] = curve.id;
    }
    curve.vertices = std::move(chain);
    out.regions[curve.region_a].curves.push_back(curve.id);
    out.regions[curve.region_b].curves.push_back(curve.id);
    out.curves.push_back(std::move(curve));
  };

  // Segments between feature vertices.
  for (index_t v0 = 0; v0 < np; ++v0) {
    if (!is_feature(v0)) continue;
    out.vertex_class[v0] = 3;
    for (index_t i = offset[v0]; i < offset[v0 + 1]; ++i) {
      const index_t e0 = incident[i];
      if (used[e0]) continue;
      std::vector<index_t> chain{v0};
      index_t e = e0, v = v0;
      for (;;) {
        used[e] = 1;
        v = other_end(e, v);
        chain.push_back(v);
        if (is_feature(v)) break;
        index_t next = kInvalidIndex;
        for (index_t j = offset[v]; j < offset[v + 1]; ++j)
          if (!used[incident[j]]) next = incident[j];
        if (next < 0) break;
        e = next;
      }
      emit(std::move(chain), false, e0);
    }
  }
  // Loops: what is left has no feature vertex.
  for (index_t e0 = 0; e0 < static_cast<index_t>(edges.size()); ++e0) {
    if (used[e0]) continue;
    std::vector<index_t> chain{edges[e0].a};
    index_t e = e0, v = edges[e0].a;
    for (;;) {
      used[e] = 1;
      v = other_end(e, v);
      if (v == chain.front()) break;
      chain.push_back(v);
      index_t next = kInvalidIndex;
      for (index_t j = offset[v]; j < offset[v + 1]; ++j)
        if (!used[incident[j]]) next = incident[j];
      if (next < 0) break;
      e = next;
    }
    emit(std::move(chain), true, e0);
  }
}

}  // namespace segment
}  // namespace femorph
