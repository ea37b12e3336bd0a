// The segmentation of thesis 2.4 (Fig. 2.6): A11 sharp edges, A12
// curvature, A13 planes, cylinders, cones, spheres, A14 tori, A15 LM
// refinement, A16 boundary curves.
#include "segment/segmentation_state.h"

#include <chrono>

namespace femorph {

using segment::State;

Status segment_surface(const SurfaceMesh& surface, const SegmentationParams& params, Segmentation& out,
                       const SegmentationProgress& progress) {
  out = Segmentation();
  if (surface.num_triangles() == 0) return Status::failure("the surface has no triangles");
  if (!(params.distance_tolerance > 0)) return Status::failure("the distance tolerance must be positive");

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last = start;
  auto lap = [&last]() {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - last).count();
    last = now;
    return s;
  };
  auto report = [&](double fraction, const char* step) { return !progress || progress(fraction, step); };
  const Status aborted = Status::failure("segmentation aborted");

  State st(surface, params);
  st.triangle_region.assign(static_cast<std::size_t>(surface.num_triangles()), kInvalidIndex);
  st.tolerance = params.distance_tolerance * surface.mean_edge_length;
  {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : surface.points) box.extend(p);
    st.scale = std::max(box.diagonal().norm(), 1e-300);
  }

  if (!report(0.0, "sharp edges")) return aborted;
  st.sharp = detect_sharp_edges(surface, degrees_to_radians(params.sharp_angle_deg));
  out.times.sharp_edges = lap();
  if (!report(0.05, "curvature")) return aborted;
  st.curvature = normal_tensor_curvature(surface, st.sharp);
  out.times.curvature = lap();
  if (!report(0.15, "planar regions")) return aborted;
  segment::extract_planar_regions(st);
  out.times.planes = lap();
  if (!report(0.3, "cylindrical regions")) return aborted;
  segment::extract_cylindrical_regions(st);
  out.times.cylinders = lap();
  if (!report(0.45, "conical regions")) return aborted;
  segment::extract_conical_regions(st);
  out.times.cones = lap();
  if (!report(0.55, "spherical regions")) return aborted;
  segment::extract_spherical_regions(st);
  out.times.spheres = lap();
  if (!report(0.65, "torus regions")) return aborted;
  segment::extract_torus_regions(st);
  out.times.tori = lap();
  segment::classify_remaining_regions(st);
  out.times.remaining = lap();
  segment::merge_equal_regions(st);
  segment::reestimate_region_boundaries(st);
  segment::merge_equal_regions(st);  // regions the re-estimation left tiny
  // Local fits of a surface they are not (freeform faces; on fine meshes,
  // strips of a torus taken for cylinders) dissolve, the parts are refitted
  // as a whole, and the real faces take back their triangles.
  // A chain of local fits (an extrusion cut into cylinder strips) goes one
  // link per round, from the dissolved side.
  constexpr int kMaxDissolveRounds = 16;
  for (int round = 0; round < kMaxDissolveRounds && segment::dissolve_ambiguous_regions(st); ++round) {
    segment::reestimate_region_boundaries(st);
    segment::absorb_unknown_triangles(st);
    segment::merge_equal_regions(st);
  }
  // Fragments of narrow faces between approximate curves (thesis 2.4.4's
  // false regions) join their neighbours.
  segment::absorb_fragment_regions(st);
  out.times.cleanup = lap();
  if (!report(0.8, "fit refinement")) return aborted;
  segment::refine_region_fits(st);
  out.times.refinement = lap();
  if (!report(0.9, "boundary curves")) return aborted;

  // Compact: live regions get ids 0..n-1 in order of first triangle.
  std::vector<index_t> id(st.regions.size(), kInvalidIndex);
  out.triangle_region.resize(static_cast<std::size_t>(surface.num_triangles()));
  for (index_t f = 0; f < surface.num_triangles(); ++f) {
    const index_t r = st.triangle_region[f];
    if (id[r] < 0) {
      id[r] = static_cast<index_t>(out.regions.size());
      const segment::WorkRegion& w = st.regions[r];
      Region region;
      region.id = id[r];
      region.type = w.type;
      region.surface = w.surface;
      region.surface.type = w.type;
      region.fit_rms = w.fit_rms;
      region.fit_max = w.fit_max;
      out.regions.push_back(region);
    }
    out.triangle_region[f] = id[r];
    Region& region = out.regions[id[r]];
    region.area += surface.areas[f];
    ++region.triangle_count;
  }
  segment::build_region_graph(st, out);
  segment::recognize_boundary_curves(st, out);
  out.times.curves = lap();
  out.times.total = std::chrono::duration<double>(Clock::now() - start).count();
  std::size_t unknown = 0;
  for (const Region& r : out.regions) unknown += r.type == SurfaceType::Unknown;
  if (unknown)
    st.warnings.push_back(std::to_string(unknown) +
                          " region(s) fit no plane, cylinder, cone, sphere or torus and are left unknown");
  out.warnings = std::move(st.warnings);
  report(1.0, "done");
  return Status::success();
}

}  // namespace femorph
