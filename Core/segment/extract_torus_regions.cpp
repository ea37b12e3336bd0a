// Torus region extraction, thesis 2.4.4 (A14): the surface left after the
// planar and quadric extraction is split by the sign of the Gaussian
// curvature (Fig. 2.12); each part gets a RANSAC torus (Fig. 2.14) and
// region integration; false regions (Fig. 2.13) are merged, and a "torus"
// that a sphere fits as well becomes a sphere (fillet junctions).
#include "segment/segmentation_state.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

namespace {

/// Vertices of the triangles with their maximum-curvature directions, for
/// the torus RANSAC's axis planes (Fig. 2.14 (a)).
std::vector<Vec3> max_directions(const State& st, const std::vector<index_t>& vertices) {
  std::vector<Vec3> d;
  d.reserve(vertices.size());
  for (index_t v : vertices) d.push_back(st.curvature.vertex_valid[v] ? st.curvature.vertex_dir_max[v] : Vec3::Zero());
  return d;
}

/// Type 1 and 2 false regions of Fig. 2.13, generalised: a small region whose
/// triangles a neighbouring torus also fits is merged into it.
void merge_false_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  for (std::size_t r = 0; r < st.regions.size(); ++r) {
    WorkRegion& small = st.regions[r];
    if (!small.alive || small.type == SurfaceType::Torus) continue;
    // Neighbouring torus regions, by shared edge count.
    std::vector<std::pair<int, index_t>> shared;
    for (index_t f : small.triangles)
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0) continue;
        const index_t o = st.triangle_region[g];
        if (o < 0 || o == static_cast<index_t>(r) || st.regions[o].type != SurfaceType::Torus) continue;
        auto it = std::find_if(shared.begin(), shared.end(), [&](const auto& p) { return p.second == o; });
        if (it == shared.end()) shared.emplace_back(1, o);
        else ++it->first;
      }
    std::sort(shared.rbegin(), shared.rend());
    for (const auto& [count, o] : shared)
      if (st.absorb_if_near(static_cast<index_t>(r), o)) break;
  }
}

}  // namespace

void extract_torus_regions(State& st) {
  constexpr std::size_t kMinTorusPart = 12;
  const Curvature& c = st.curvature;
  // Fig. 2.12: neighbouring torus regions have opposite signs of the Gaussian
  // curvature; grow over unassigned triangles of one sign.
  for (int sign : {-1, 1}) {
    auto member = [&](index_t f) {
      if (st.triangle_region[f] >= 0 || !c.triangle_valid[f]) return false;
      const double k = c.triangle_k_max[f] * c.triangle_k_min[f];
      return sign > 0 ? k > 0 : k <= 0;
    };
    std::vector<std::vector<index_t>> parts = connected_components(st, true, member);
    std::sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
    for (std::vector<index_t>& part : parts) {
      part.erase(std::remove_if(part.begin(), part.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
                 part.end());
      // Small pieces are left to classify_remaining_regions, whose whole-patch
      // fits are cheaper than a torus RANSAC per fragment (fine meshes have
      // many where the Gaussian curvature changes sign).
      if (part.size() < kMinTorusPart) continue;
      const std::vector<index_t> vertices = st.vertices_of(part);
      const std::vector<Vec3> dirs = max_directions(st, vertices);
      const FitResult fit = fit_region(st, SurfaceType::Torus, part, &dirs);
      if (!fit.ok) continue;
      WorkRegion region = integrate_region(st, SurfaceType::Torus, part, fit);
      if (region.alive && region.triangles.size() >= 2) add_region(st, std::move(region));
    }
  }
  merge_false_regions(st);
  // Junctions of fillets are small spheres often taken for tori (2.4.4,
  // end): a torus region that a sphere fits as well is a sphere.
  for (WorkRegion& region : st.regions) {
    if (!region.alive || region.type != SurfaceType::Torus) continue;
    if (st.vertices_of(region.triangles).size() < min_vertices(SurfaceType::Torus)) continue;
    const FitResult sphere = fit_region(st, SurfaceType::Sphere, region.triangles);
    if (!sphere.ok || sphere.max_abs > st.tolerance || !plausible_fit(st, sphere.surface, region.triangles) ||
        simpler_type_fits(st, SurfaceType::Sphere, region.triangles, sphere.max_abs))
      continue;
    bool all_on = true;
    for (index_t f : region.triangles) all_on = all_on && st.triangle_near(sphere.surface, f);
    if (!all_on) continue;
    region.type = SurfaceType::Sphere;
    region.surface = sphere.surface;
    region.fit_rms = sphere.rms;
    region.fit_max = sphere.max_abs;
  }
}

}  // namespace segment
}  // namespace femorph
