// Planar region extraction, thesis 2.4.3 (A13), the first of the sequential
// extractions of Fig. 2.7.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

void extract_planar_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  // Fig. 2.8 (a): the variance (Eq. 2.6) of the unit normals around a vertex
  // is 0 on a plane. |n - n_bar|^2 = 2 (1 - cos angle): the threshold admits
  // normals within the plane angle tolerance.
  const double max_variance = 2.0 * (1.0 - std::cos(degrees_to_radians(st.params.plane_angle_tolerance_deg)));
  std::vector<char> planar_vertex(static_cast<std::size_t>(s.num_points()), 0);
  std::vector<Vec3> ring;
#pragma omp parallel for schedule(static) private(ring) if(s.num_points() >= kParallelMinItems)
  for (index_t v = 0; v < s.num_points(); ++v) {
    ring.clear();
    for (index_t i = s.vertex_offsets[v]; i < s.vertex_offsets[v + 1]; ++i) {
      const Vec3& n = s.normals[s.vertex_triangles[i]];
      if (n.squaredNorm() > 0) ring.push_back(n);
    }
    planar_vertex[v] = !ring.empty() && vector_variance(ring.data(), static_cast<int>(ring.size()), false) <= max_variance;
  }
  // Seed triangles have two or more planar vertices; seed regions are their
  // connected components.
  auto is_seed = [&](index_t f) {
    if (st.triangle_region[f] >= 0) return false;
    int count = 0;
    for (index_t v : s.triangles[f]) count += planar_vertex[v];
    return count >= 2;
  };
  std::vector<std::vector<index_t>> seeds = connected_components(st, true, is_seed);
  std::sort(seeds.begin(), seeds.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  // Region integration, largest seed first: fit, grow by distance, refit.
  for (std::vector<index_t>& seed : seeds) {
    seed.erase(std::remove_if(seed.begin(), seed.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
               seed.end());
    if (seed.empty()) continue;
    const FitResult fit = fit_region(st, SurfaceType::Plane, seed);
    if (!fit.ok || fit.max_abs > st.tolerance) continue;
    WorkRegion region = integrate_region(st, SurfaceType::Plane, seed, fit);
    if (region.alive) add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
