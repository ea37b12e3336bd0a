// Beyond the thesis: freeform (e.g. B-spline) faces must become unknown
// regions, never a patchwork of wrong primitives. Any smooth surface is
// approximated within the tolerance by small quadric patches, so region
// growing cuts a freeform face into many small regions; their boundaries are
// not real: triangles along them lie on both neighbours' surfaces. Along a
// real boundary between two CAD faces, even a tangent (G1) one, the surfaces
// part quadratically and the neighbour's triangles lie off each other's
// surface. Regions with such a blurred boundary on both sides are dissolved
// into unknown regions when one of them is also stretched to the tolerance
// (its fit's rms distance above a fifth of it): a local approximation grows
// until the tolerance stops it, so its vertices spread over the whole band,
// while a CAD face fits its vertices to the noise of the mesh, far below
// (this keeps short G1 boundaries between small fillets, which can look
// blurred on a jittered mesh).
#include "segment/segmentation_state.h"

#include <map>

namespace femorph {
namespace segment {

void dissolve_ambiguous_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  constexpr double kNear = 4.0;
  // (a, b) -> (triangles of a along b, of which on b's surface)
  std::map<std::pair<index_t, index_t>, std::pair<int, int>> along;
  for (index_t f = 0; f < s.num_triangles(); ++f) {
    const index_t a = st.triangle_region[f];
    if (a < 0 || st.regions[a].type == SurfaceType::Unknown) continue;
    index_t seen = kInvalidIndex;
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g < 0) continue;
      const index_t b = st.triangle_region[g];
      if (b < 0 || b == a || b == seen || st.regions[b].type == SurfaceType::Unknown) continue;
      seen = b;
      auto& c = along[{a, b}];
      ++c.first;
      c.second += st.triangle_distance(st.regions[b].surface, f) <= kNear * st.tolerance;
    }
  }
  constexpr double kBlurred = 0.75;
  constexpr double kStretched = 0.2;
  std::vector<char> dissolve(st.regions.size(), 0);
  for (const auto& [pair, c] : along) {
    const auto back = along.find({pair.second, pair.first});
    if (back == along.end()) continue;
    const bool blurred = c.second >= kBlurred * c.first && back->second.second >= kBlurred * back->second.first;
    const bool stretched = st.regions[pair.first].fit_rms > kStretched * st.tolerance ||
                           st.regions[pair.second].fit_rms > kStretched * st.tolerance;
    if (blurred && stretched) dissolve[pair.first] = dissolve[pair.second] = 1;
  }
  bool any = false;
  for (std::size_t r = 0; r < st.regions.size(); ++r)
    if (dissolve[r]) {
      st.regions[r].type = SurfaceType::Unknown;
      any = true;
    }
  if (!any) return;
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
    WorkRegion region;
    region.type = SurfaceType::Unknown;
    region.triangles = part;
    add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
