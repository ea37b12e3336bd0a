// Spherical region extraction, thesis 2.4.3 (A13): on a sphere the principal
// directions have no consistency (Fig. 2.8 (d)); seeds are triangles whose
// vertices' directions differ by more than the sphere direction angle.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

void extract_spherical_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  const Curvature& c = st.curvature;
  const double cos_angle = std::cos(degrees_to_radians(st.params.sphere_direction_angle_deg));
  constexpr double kMinCurvatureTimesEdge = 2e-3;
  auto is_seed = [&](index_t f) {
    if (st.triangle_region[f] >= 0) return false;
    const Tri& t = s.triangles[f];
    for (index_t v : t)
      if (!c.vertex_valid[v] || std::abs(c.vertex_k_max[v]) * s.mean_edge_length <= kMinCurvatureTimesEdge)
        return false;
    // Umbilic: both curvatures alike, and directions differing a lot.
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        if (std::abs(c.vertex_dir_max[t[i]].dot(c.vertex_dir_max[t[j]])) < cos_angle) return true;
    return false;
  };
  std::vector<std::vector<index_t>> seeds = connected_components(st, true, is_seed);
  std::sort(seeds.begin(), seeds.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  for (std::vector<index_t>& seed : seeds) {
    seed.erase(std::remove_if(seed.begin(), seed.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
               seed.end());
    if (seed.empty()) continue;
    // A lone seed triangle has three vertices: too few for a sphere. Widen
    // the seed by its unassigned neighbours (the fit keeps what lies on it).
    if (st.vertices_of(seed).size() < 6) {
      const std::size_t n = seed.size();
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
          const index_t g = s.neighbors[seed[i]][k];
          if (g >= 0 && st.triangle_region[g] < 0 && std::find(seed.begin(), seed.end(), g) == seed.end())
            seed.push_back(g);
        }
    }
    const FitResult fit = fit_region(st, SurfaceType::Sphere, seed);
    if (!fit.ok || fit.surface.radius <= 0) continue;
    WorkRegion region = integrate_region(st, SurfaceType::Sphere, seed, fit);
    if (region.alive && region.triangles.size() >= 2) add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
