// Planar region extraction, thesis 2.4.3 (A13), the first of the sequential
// extractions of Fig. 2.7.
#include "segment/segmentation_state.h"
#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

namespace {

/// The mesh's precision, measured on its planar seeds (the median distance
/// of a seed's inner vertices to their plane, median over seeds weighted by
/// size), and the tolerance tightened to it when adaptive_tolerance is on.
/// Also the precision of the boundary curves: a CAD mesh's nodes inside a
/// face lie on it exactly, those on its edge curves only as well as the
/// file's curves approximate the face intersections. The curve tolerance is
/// six times the 0.9-quantile of the seeds' border vertex distances to the
/// planes of their inner vertices (border vertices lie on the curves or next
/// to them), capped at 1e-3 of the part: beyond that a node is off the face,
/// not on its curve. The tolerance is not tightened below a quarter of the
/// curve tolerance: a face one or two triangles wide between approximate
/// curves has no vertex closer to it than that, and two faces meeting at an
/// angle too small to show over that distance cannot be told apart along
/// their curve anyway. The precision stays what it measured (dissolving
/// local fits of freeform faces compares with it).
void measure_precision(State& st, const std::vector<std::vector<index_t>>& seeds,
                       const std::vector<FitResult>& fits) {
  constexpr std::size_t kMinInner = 6;
  std::vector<std::pair<double, double>> medians;  // (median distance, triangles)
  std::vector<double> border;                      // border vertex distances
  double total = 0;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    if (!fits[i].ok || seeds[i].size() < 4) continue;
    const std::vector<index_t> vertices = st.vertices_of(seeds[i]);
    const std::vector<char> inner = st.inner_mask(seeds[i], vertices);
    // The plane of the inner vertices where there are enough of them: off
    // the boundary curves, the median tells the mesh's precision, not how
    // far the curves tilt a fit of all vertices.
    std::vector<Vec3> inner_points;
    for (std::size_t k = 0; k < vertices.size(); ++k)
      if (inner[k]) inner_points.push_back(st.surface.points[vertices[k]]);
    FitResult plane = fits[i];
    const bool by_inner = inner_points.size() >= kMinInner && 4 * inner_points.size() >= vertices.size();
    if (by_inner) plane = fit_plane(inner_points, nullptr);
    if (!plane.ok || plane.max_abs > st.tolerance) continue;
    std::vector<double> d;
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      const double e = distance(plane.surface, st.surface.points[vertices[k]]);
      if (!inner[k]) border.push_back(e);
      if (inner[k] || !by_inner) d.push_back(e);
    }
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    medians.emplace_back(d[d.size() / 2], static_cast<double>(seeds[i].size()));
    total += static_cast<double>(seeds[i].size());
  }
  if (medians.empty()) return;
  if (!border.empty()) {
    constexpr double kQuantile = 0.9, kCurveFactor = 6.0, kMaxCurveRelative = 1e-3;
    auto q = border.begin() + static_cast<std::ptrdiff_t>(kQuantile * static_cast<double>(border.size() - 1));
    std::nth_element(border.begin(), q, border.end());
    st.curve_tolerance = std::min(kCurveFactor * *q, kMaxCurveRelative * st.scale);
  }
  std::sort(medians.begin(), medians.end());
  double seen = 0;
  for (const auto& [m, w] : medians) {
    seen += w;
    if (seen >= 0.5 * total) {
      st.noise = m;
      break;
    }
  }
  if (!st.params.adaptive_tolerance) return;
  constexpr double kNoiseFactor = 1e4;
  constexpr double kMinRelative = 1e-6;
  constexpr double kCurveRatio = 4.0;
  st.precision = std::max(kNoiseFactor * st.noise, kMinRelative * st.scale);
  st.tolerance = std::min(st.tolerance, std::max(st.precision, st.curve_tolerance / kCurveRatio));
}

}  // namespace

void extract_planar_regions(State& st) {
  const SurfaceMesh& s = st.surface;
  // Fig. 2.8 (a): the variance (Eq. 2.6) of the unit normals around a vertex
  // is 0 on a plane. |n - n_bar|^2 = 2 (1 - cos angle): the threshold admits
  // normals within the plane angle tolerance.
  const double max_variance = 2.0 * (1.0 - std::cos(degrees_to_radians(st.params.plane_angle_tolerance_deg)));
  std::vector<char> planar_vertex(static_cast<std::size_t>(s.num_points()), 0);
  parallel_for_chunks(s.num_points(), [&](long begin, long end, int) {
    std::vector<Vec3> ring;
    for (index_t v = static_cast<index_t>(begin); v < static_cast<index_t>(end); ++v) {
      ring.clear();
      for (index_t i = s.vertex_offsets[v]; i < s.vertex_offsets[v + 1]; ++i) {
        const Vec3& n = s.normals[s.vertex_triangles[i]];
        if (n.squaredNorm() > 0) ring.push_back(n);
      }
      planar_vertex[v] =
          !ring.empty() && vector_variance(ring.data(), static_cast<int>(ring.size()), false) <= max_variance;
    }
  });
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
  // On fine meshes a seed also holds a band of nearly flat triangles of the
  // surfaces tangent to the plane (fillets): trim what the fit leaves off and
  // refit, a few times.
  std::vector<FitResult> fits(seeds.size());
  auto trim_and_fit = [&](std::size_t i) {
    std::vector<index_t>& seed = seeds[i];
    FitResult fit = fits[i].ok ? fits[i] : fit_region(st, SurfaceType::Plane, seed);
    for (int trim = 0; trim < 4 && fit.ok && fit.max_abs > st.tolerance; ++trim) {
      std::vector<index_t> kept;
      for (index_t f : seed)
        if (st.curve_tolerance > st.tolerance ? st.triangle_near(fit.surface, f)
                                              : st.triangle_distance(fit.surface, f) <= st.tolerance)
          kept.push_back(f);
      if (kept.empty() || kept.size() == seed.size()) break;
      seed.swap(kept);
      fit = fit_region(st, SurfaceType::Plane, seed);
    }
    fits[i] = fit;
  };
  for (std::size_t i = 0; i < seeds.size(); ++i) trim_and_fit(i);
  // The tolerance tightened to the mesh's precision trims the seeds again.
  const double before = st.tolerance;
  measure_precision(st, seeds, fits);
  // Refit first where the boundary curves are looser than the rest: the fits
  // so far took every vertex.
  if (st.tolerance < before || st.curve_tolerance > st.tolerance)
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      if (st.curve_tolerance > st.tolerance) fits[i].ok = false;
      trim_and_fit(i);
    }
  // Region integration, largest seed first: fit, grow by distance, refit.
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    std::vector<index_t>& seed = seeds[i];
    if (!fits[i].ok || fits[i].max_abs > st.tolerance) continue;
    seed.erase(std::remove_if(seed.begin(), seed.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
               seed.end());
    if (seed.empty()) continue;
    WorkRegion region = integrate_region(st, SurfaceType::Plane, seed, fits[i]);
    if (region.alive) add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
