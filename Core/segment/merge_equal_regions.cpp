// Adjacent regions of one type with the same fitted surface are one surface
// region (a cylinder reached from two seeds, a plane cut by a seam).
#include "segment/segmentation_state.h"

#include <numeric>

namespace femorph {
namespace segment {

void merge_equal_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  const index_t n = static_cast<index_t>(st.regions.size());
  std::vector<index_t> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const double rel = 1e3 * st.tolerance / st.scale;  // loose: both fits are accurate
  for (index_t f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g < 0 || g < f) continue;
      const index_t a = find(st.triangle_region[f]), b = find(st.triangle_region[g]);
      if (a < 0 || b < 0 || a == b) continue;
      const WorkRegion& ra = st.regions[a];
      const WorkRegion& rb = st.regions[b];
      if (ra.type != rb.type || ra.type == SurfaceType::Unknown) continue;
      if (!same_surface(ra.surface, rb.surface, rel, st.scale, 1e-3)) continue;
      // Check for real: every triangle of b lies on a's surface.
      bool all_on = true;
      for (index_t h : rb.triangles) all_on = all_on && st.triangle_on(ra.surface, h);
      if (!all_on) continue;
      parent[b] = a;
    }
  for (index_t f = 0; f < s.num_triangles(); ++f)
    if (st.triangle_region[f] >= 0) st.triangle_region[f] = find(st.triangle_region[f]);
  for (WorkRegion& r : st.regions) r.triangles.clear();
  for (index_t f = 0; f < s.num_triangles(); ++f)
    if (st.triangle_region[f] >= 0) st.regions[st.triangle_region[f]].triangles.push_back(f);
  for (WorkRegion& r : st.regions) r.alive = !r.triangles.empty();
}

}  // namespace segment
}  // namespace femorph
