// Cylindrical region extraction, thesis 2.4.3 (A13): seeds where the
// minimum-curvature directions agree (Fig. 2.8 (b)), the Gaussian sphere fit
// of Fig. 2.9, and the check that rejects cones.
#include "segment/segmentation_state.h"
#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

namespace {

/// A triangle with a curvature estimate that is not flat.
bool curved(const State& st, index_t f) {
  constexpr double kMinCurvatureTimesEdge = 2e-3;
  return st.curvature.triangle_valid[f] &&
         std::abs(st.curvature.triangle_k_max[f]) * st.surface.mean_edge_length > kMinCurvatureTimesEdge;
}

}  // namespace

/// Seed regions of triangles whose minimum-curvature directions agree within
/// `angle` with their neighbours and whose maximum curvatures have one sign
/// (thesis 2.4.3.2, cylindrical and conical initial seed regions).
std::vector<std::vector<index_t>> direction_seed_regions(const State& st, double angle) {
  const SurfaceMesh& s = st.surface;
  const Curvature& c = st.curvature;
  const double cos_angle = std::cos(angle);
  const double max_variance = 2.0 * (1.0 - cos_angle);
  std::vector<char> seed(static_cast<std::size_t>(s.num_triangles()), 0);
  parallel_for_chunks(
      static_cast<long>(s.num_triangles()),
      [&](long begin, long end, int) {
        for (index_t f = static_cast<index_t>(begin); f < static_cast<index_t>(end); ++f) {
          if (st.triangle_region[f] >= 0 || !curved(st, f)) continue;
          Vec3 dirs[4];
          int n = 0;
          dirs[n++] = c.triangle_dir_min[f];
          for (int k = 0; k < 3; ++k) {
            const index_t g = s.neighbors[f][k];
            if (g >= 0 && c.triangle_valid[g]) dirs[n++] = c.triangle_dir_min[g];
          }
          seed[f] = n >= 3 && vector_variance(dirs, n, true) <= max_variance;
        }
      },
      kParallelMinItems);
  // Grow seed regions over neighbours with agreeing directions and the same
  // sign of the maximum curvature.
  std::vector<std::vector<index_t>> regions;
  std::vector<char> taken(seed.size(), 0);
  std::vector<index_t> stack;
  for (index_t f0 = 0; f0 < s.num_triangles(); ++f0) {
    if (!seed[f0] || taken[f0]) continue;
    regions.emplace_back();
    taken[f0] = 1;
    stack.assign(1, f0);
    while (!stack.empty()) {
      const index_t f = stack.back();
      stack.pop_back();
      regions.back().push_back(f);
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0 || taken[g] || st.sharp.edge[3 * f + k] || st.triangle_region[g] >= 0 || !curved(st, g)) continue;
        if (std::abs(c.triangle_dir_min[f].dot(c.triangle_dir_min[g])) < cos_angle) continue;
        if ((c.triangle_k_max[f] > 0) != (c.triangle_k_max[g] > 0)) continue;
        taken[g] = 1;
        stack.push_back(g);
      }
    }
  }
  std::sort(regions.begin(), regions.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return regions;
}

void extract_cylindrical_regions(State& st) {
  // Normals of a cylinder lie on a great circle of the Gaussian sphere: the
  // plane fitted to them passes through its centre (2.4.3.3). A cone's are
  // offset by sin(half angle).
  constexpr double kMaxGaussianOffset = 0.02;
  constexpr std::size_t kMinSeed = 3;
  const double angle = degrees_to_radians(st.params.cylinder_angle_tolerance_deg);
  for (std::vector<index_t>& seed : direction_seed_regions(st, angle)) {
    seed.erase(std::remove_if(seed.begin(), seed.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
               seed.end());
    if (seed.size() < kMinSeed) continue;
    const FitResult fit = fit_region(st, SurfaceType::Cylinder, seed);
    if (!fit.ok || fit.max_abs > st.tolerance) continue;
    WorkRegion region = integrate_region(st, SurfaceType::Cylinder, seed, fit);
    if (!region.alive) continue;
    std::vector<Vec3> normals;
    for (index_t f : region.triangles) normals.push_back(st.surface.normals[f]);
    if (gaussian_sphere_plane_offset(normals) > kMaxGaussianOffset) continue;  // a cone: left for later
    add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
