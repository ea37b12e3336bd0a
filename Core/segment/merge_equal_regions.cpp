// Adjacent regions of one type that are one surface become one region (a
// cylinder reached from two seeds, a torus split by the sign of a noisy
// Gaussian curvature): merged when every triangle of the smaller lies on
// the larger one's fitted surface. A tiny region (one or two triangles, as
// seeds leave along G1 boundaries) is absorbed likewise whatever its type.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <set>

namespace femorph {
namespace segment {

void merge_equal_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  constexpr std::size_t kTiny = 2;
  for (int pass = 0; pass < 8; ++pass) {
    // Adjacent pairs of one type.
    std::set<std::pair<index_t, index_t>> pairs;
    for (index_t f = 0; f < s.num_triangles(); ++f)
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0) continue;
        index_t a = st.triangle_region[f], b = st.triangle_region[g];
        if (a < 0 || b < 0 || a == b) continue;
        const bool tiny = st.regions[a].triangles.size() <= kTiny || st.regions[b].triangles.size() <= kTiny;
        if (!tiny && st.regions[a].type != st.regions[b].type) continue;
        pairs.emplace(std::min(a, b), std::max(a, b));
      }
    int merged = 0;
    std::vector<char> grown(st.regions.size(), 0);
    for (auto [a, b] : pairs) {
      if (!st.regions[a].alive || !st.regions[b].alive) continue;
      if (st.regions[a].triangles.size() < st.regions[b].triangles.size()) std::swap(a, b);
      if (st.regions[a].type == SurfaceType::Unknown || !st.absorb_if_near(b, a)) continue;
      grown[a] = 1;
      ++merged;
    }
    if (!merged) break;
    // Refit the grown regions before the next pass.
    for (std::size_t i = 0; i < st.regions.size(); ++i) {
      WorkRegion& r = st.regions[i];
      if (!grown[i] || !r.alive || r.type == SurfaceType::Unknown) continue;
      const FitResult fit = refit_region(st, r.type, r.surface, r.triangles);
      if (fit.ok) r.surface = fit.surface;
    }
  }
}

}  // namespace segment
}  // namespace femorph
