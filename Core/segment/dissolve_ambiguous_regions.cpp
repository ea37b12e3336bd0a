// Beyond the thesis: freeform (e.g. B-spline) faces must become unknown
// regions, never a patchwork of wrong primitives. Any smooth surface is
// approximated within the tolerance by small quadric patches, so region
// growing cuts a freeform face into many small regions; their boundaries are
// not real: triangles along them lie on both neighbours' surfaces. Along a
// real boundary between two CAD faces, even a tangent (G1) one, the surfaces
// part quadratically and the neighbour's triangles lie off each other's
// surface. A region with such a blurred boundary on both sides is dissolved
// into unknown regions when it is also stretched to the tolerance
// (its fit's rms distance above a fifth of it): a local approximation grows
// until the tolerance stops it, so its vertices spread over the whole band,
// while a CAD face fits its vertices to the noise of the mesh, far below
// (this keeps short G1 boundaries between small fillets, which can look
// blurred on a jittered mesh). Where the boundary curves are approximate,
// the tolerance stays well above the mesh's precision, and a fit whose inner
// vertices lie off it by more than the precision goes whatever its borders.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <map>

namespace femorph {
namespace segment {

void absorb_unknown_triangles(State& st) {
  const SurfaceMesh& s = st.surface;
  std::vector<index_t> frontier;
  for (std::size_t r = 0; r < st.regions.size(); ++r) {
    WorkRegion& region = st.regions[r];
    if (!region.alive || region.type == SurfaceType::Unknown) continue;
    frontier = region.triangles;
    while (!frontier.empty()) {
      const index_t f = frontier.back();
      frontier.pop_back();
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0) continue;
        const index_t o = st.triangle_region[g];
        if (o < 0 || st.regions[o].type != SurfaceType::Unknown || !st.triangle_near(region.surface, g)) continue;
        st.triangle_region[g] = static_cast<index_t>(r);
        region.triangles.push_back(g);
        frontier.push_back(g);
      }
    }
  }
}

bool dissolve_ambiguous_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  constexpr double kNear = 4.0;
  // (a, b) -> (triangles of a along b, of which on b's surface)
  std::map<std::pair<index_t, index_t>, std::pair<int, int>> along;
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    const index_t a = st.triangle_region[f];
    if (a < 0) continue;
    index_t seen = kInvalidIndex;
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g < 0) continue;
      const index_t b = st.triangle_region[g];
      if (b < 0 || b == a || b == seen || st.regions[b].type == SurfaceType::Unknown) continue;
      seen = b;
      auto& c = along[{a, b}];
      ++c.first;
      // Judged on f's vertices away from b (its border vertices lie on a
      // boundary curve, exact or not).
      c.second += st.triangle_distance_off(st.regions[b].surface, f, b) <= kNear * st.tolerance;
    }
  }
  constexpr double kBlurred = 0.75;
  constexpr double kStretched = 0.2;
  constexpr std::size_t kSmallFit = 30;
  // The mesh's own precision (measured on its planar seeds; at least 1e-12
  // of the part). A fit a thousand times worse than that approximates
  // rather than fits: on a mesh whose nodes lie on their CAD surfaces to
  // 1e-14, a cylinder fitting a strip of a B-spline extrusion to 4e-4 is a
  // local approximation.
  const double noise = std::max(st.noise, 1e-12 * st.scale);
  constexpr double kInexact = 1e3;
  // Judged robustly: a real face that took a few triangles of a nearly
  // tangent freeform neighbour still fits most of its vertices exactly, but
  // those few tilt its least-squares fit. So: refit on the better half of
  // the vertices, then take the median distance of all of them.
  std::vector<double> median(st.regions.size(), -1);
  std::vector<char> by_inner(st.regions.size(), 0);  // median over inner vertices only
  auto median_distance = [&](const SurfacePrimitive& surface, const std::vector<Vec3>& points) {
    std::vector<double> d;
    d.reserve(points.size());
    for (const Vec3& p : points) d.push_back(distance(surface, p));
    if (d.empty()) return 0.0;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return d[d.size() / 2];
  };
  auto robust_median = [&](const WorkRegion& r, const std::vector<Vec3>& points) {
    const double m = median_distance(r.surface, points);
    std::vector<Vec3> better;
    for (const Vec3& p : points)
      if (distance(r.surface, p) <= m) better.push_back(p);
    const FitResult refit =
        r.type == SurfaceType::Plane ? fit_plane(better, nullptr) : refine_fit_lm(r.surface, better);
    return refit.ok ? std::min(m, median_distance(refit.surface, points)) : m;
  };
  auto stretched = [&](const WorkRegion& r) {
    const std::size_t i = static_cast<std::size_t>(&r - st.regions.data());
    if (median[i] < 0) {
      const std::vector<index_t> chosen = st.fit_vertices(r.triangles, 2 * min_vertices(r.type));
      by_inner[i] = chosen.size() < st.vertices_of(r.triangles).size();
      median[i] = robust_median(r, st.positions(chosen));
    }
    return median[i] > kStretched * st.tolerance || median[i] > kInexact * noise;
  };
  // The vertices of region r that touch no other fitted region: inside it
  // or on its border with unknown ones, so on no boundary curve between
  // fitted faces (a local fit's border inside a freeform face is no CAD
  // curve, and its vertices are as exact as the inner ones).
  auto off_curves = [&](index_t r) {
    std::vector<index_t> kept;
    for (index_t v : st.vertices_of(st.regions[r].triangles)) {
      bool alone = true;
      for (index_t k = s.vertex_offsets[v]; k < s.vertex_offsets[v + 1] && alone; ++k) {
        const index_t o = st.triangle_region[s.vertex_triangles[k]];
        alone = o == r || o < 0 || st.regions[o].type == SurfaceType::Unknown;
      }
      if (alone) kept.push_back(v);
    }
    return kept;
  };
  std::vector<char> dissolve(st.regions.size(), 0);
  // Where the tolerance is looser than the mesh's precision (approximate
  // boundary curves keep it up), a fit within the tolerance may still be a
  // local approximation: the vertices inside a CAD face lie on it to the
  // precision. A region whose inner vertices do not is no face of its type,
  // whatever its boundaries look like.
  if (st.exact_tolerance() < st.tolerance)
    for (std::size_t r = 0; r < st.regions.size(); ++r) {
      const WorkRegion& region = st.regions[r];
      if (!region.alive || region.type == SurfaceType::Unknown) continue;
      stretched(region);
      if (by_inner[r]) {
        if (median[r] > st.exact_tolerance()) dissolve[r] = 1;
        continue;
      }
      // Too few inner vertices (a small local fit): judged on those off
      // the curves between fitted faces when they are enough.
      const std::vector<index_t> kept = off_curves(static_cast<index_t>(r));
      const std::size_t all = st.vertices_of(region.triangles).size();
      if (kept.size() >= 2 * min_vertices(region.type) && 4 * kept.size() >= all &&
          robust_median(region, st.positions(kept)) > st.exact_tolerance())
        dissolve[r] = 1;
    }
  for (const auto& [pair, c] : along) {
    // A small fit whose surface runs on into an unknown neighbour (that
    // neighbour's triangles along it lie on it) is a piece of the same
    // freeform face, e.g. the strongly curved end of an extrusion taken for a
    // cylinder.
    if (st.regions[pair.first].type == SurfaceType::Unknown) {
      WorkRegion& fitted = st.regions[pair.second];
      if (c.second >= kBlurred * c.first && (stretched(fitted) || fitted.triangles.size() < kSmallFit))
        dissolve[pair.second] = 1;
      continue;
    }
    const auto back = along.find({pair.second, pair.first});
    if (back == along.end()) continue;
    const bool blurred = c.second >= kBlurred * c.first && back->second.second >= kBlurred * back->second.first;
    const bool first_stretched = stretched(st.regions[pair.first]);
    const bool second_stretched = stretched(st.regions[pair.second]);
    // Only the stretched side goes: a CAD face next to a fragment stays.
    if (blurred && first_stretched) dissolve[pair.first] = 1;
    if (blurred && second_stretched) dissolve[pair.second] = 1;
  }
  bool any = false;
  for (std::size_t r = 0; r < st.regions.size(); ++r)
    if (dissolve[r]) {
      st.regions[r].type = SurfaceType::Unknown;
      any = true;
    }
  if (!any) return false;
  // Small fits left among the dissolved ones are fragments too: a region of
  // fewer than kFragment triangles that borders unknown regions along most of
  // its boundary, repeated until none is left.
  constexpr std::size_t kFragment = 30;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<int> edges(st.regions.size(), 0), unknown_edges(st.regions.size(), 0);
    for (index_t f = 0; f < s.num_triangles(); ++f) {
      const index_t a = st.triangle_region[f];
      if (a < 0) continue;
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0 || st.triangle_region[g] == a || st.triangle_region[g] < 0) continue;
        ++edges[a];
        unknown_edges[a] += st.regions[st.triangle_region[g]].type == SurfaceType::Unknown;
      }
    }
    for (std::size_t r = 0; r < st.regions.size(); ++r) {
      WorkRegion& region = st.regions[r];
      if (!region.alive || region.type == SurfaceType::Unknown || region.triangles.size() >= kFragment) continue;
      if (edges[r] > 0 && 2 * unknown_edges[r] >= edges[r]) {
        region.type = SurfaceType::Unknown;
        changed = true;
      }
    }
  }
  absorb_unknown_triangles(st);
  // Unknown triangles (dissolved or left unknown before) are regrouped: one
  // region per smooth part, slivers of one or two triangles cut off by a
  // sharp edge joining their neighbour.
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    const index_t r = st.triangle_region[f];
    if (r >= 0 && st.regions[r].type == SurfaceType::Unknown) st.triangle_region[f] = kInvalidIndex;
  }
  for (WorkRegion& r : st.regions)
    if (r.type == SurfaceType::Unknown) {
      r.triangles.clear();
      r.alive = false;
    }
  std::vector<std::vector<index_t>> parts =
      connected_components(st, true, [&](index_t f) { return st.triangle_region[f] < 0; });
  std::vector<index_t> part_of(static_cast<std::size_t>(s.num_triangles()), kInvalidIndex);
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (index_t f : parts[p]) part_of[f] = static_cast<index_t>(p);
  constexpr std::size_t kSliver = 2;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].size() > kSliver) continue;
    index_t into = kInvalidIndex;
    for (index_t f : parts[p])
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g >= 0 && part_of[g] >= 0 && part_of[g] != static_cast<index_t>(p) && parts[part_of[g]].size() > kSliver)
          into = part_of[g];
      }
    if (into < 0) continue;
    for (index_t f : parts[p]) part_of[f] = into;
    parts[into].insert(parts[into].end(), parts[p].begin(), parts[p].end());
    parts[p].clear();
  }
  for (const std::vector<index_t>& part : parts) {
    if (part.empty()) continue;
    // Once the local fits are gone, the part as a whole may be one surface
    // (on a fine mesh, strips of a torus fit cylinders within the tolerance).
    if (fit_patch(st, part)) continue;
    WorkRegion region;
    region.type = SurfaceType::Unknown;
    region.triangles = part;
    add_region(st, std::move(region));
  }
  return true;
}

}  // namespace segment
}  // namespace femorph
