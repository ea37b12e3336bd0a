// Dimension-driven deformation of a tet mesh (thesis 2.5, Fig. 2.19) with
// the quality improvement of 2.6 on the deformable region; a change that
// would invert tetrahedra is split into smaller steps with improvement in
// between (thesis 2.8, Fig. 2.55, future work).
#include "deform/deform_internal.h"

#include "improve/improve_target.h"
#include "improve/improve_volume.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <sstream>
#include <system_error>

namespace femorph {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double min_stretch(const TetMesh& mesh) {
  double lo = 0;
  live_stretch_range(mesh, &lo, nullptr);
  return lo;
}

/// Tets of `mask` (empty: all) with no positive volume at `points`, and
/// where the first few are.
std::size_t count_inverted(const TetMesh& mesh, const std::vector<Vec3>& points, const std::vector<std::uint8_t>& mask,
                           std::string* where = nullptr) {
  std::size_t n = 0;
  std::ostringstream os;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t) || (!mask.empty() && !mask[t])) continue;
    const Tet& T = mesh.tet(t);
    if (tet_signed_volume(points[T[0]], points[T[1]], points[T[2]], points[T[3]]) > 0) continue;
    if (n < 3) {
      const Vec3 c = (points[T[0]] + points[T[1]] + points[T[2]] + points[T[3]]) / 4;
      os << (n ? "; " : "") << "(" << c.x() << ", " << c.y() << ", " << c.z() << ")";
    }
    ++n;
  }
  if (where) *where = os.str() + (n > 3 ? "; ..." : "");
  return n;
}

std::string range_text(const DeformPlan& plan) {
  std::ostringstream os;
  os << "[" << plan.valid_min << ", " << plan.valid_max << "]";
  return os.str();
}

}  // namespace

Status deform_mesh(TetMesh& mesh, DeformRegions& regions, std::vector<BoundaryCurve>* curves,
                   const DeformOptions& options, const DeformMeshOptions& mo, DeformPlan& plan,
                   DeformReport& report) {
  const auto start = Clock::now();
  report = DeformReport();
  const auto progress = [&](double f, const char* what) { return !mo.progress || mo.progress(f, what); };

  // A fitted plane normal a rounding error away from a coordinate axis is
  // that axis: projections onto it then keep the coordinate exact (a
  // solver's input deck selects z = 0 by value).
  for (SurfacePrimitive& sp : regions.surfaces) {
    if (sp.type != SurfaceType::Plane) continue;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(std::abs(sp.axis[k]) - 1) < 1e-12) {
        const double sign = sp.axis[k] > 0 ? 1.0 : -1.0;
        sp.axis = Vec3::Zero();
        sp.axis[k] = sign;
      }
    }
  }
  RegionGraph graph = region_adjacency(mesh, regions.size());
  Status s = classify_surface_regions(mesh, regions, graph, options, plan);
  if (!s) return s;
  report.seconds_classify = seconds_since(start);
  report.current = plan.current;
  report.target = mo.target;
  report.surfaces = regions.surfaces;
  // The valid range (a search over trial values of the boundary alone) runs
  // beside the first step's region, parameterisation and repositioning,
  // which do not depend on it, on copies of the mesh and regions (a mesh's
  // queries share scratch space). It is awaited before the mesh changes.
  std::future<DeformPlan> range;
  {
    auto work = std::make_shared<std::pair<TetMesh, DeformRegions>>(mesh, regions);
    auto search = [work, p = plan, &report]() mutable {
      const auto t0 = Clock::now();
      find_valid_range(work->first, work->second, p);
      report.seconds_range = seconds_since(t0);
      return p;
    };
    try {
      range = std::async(std::launch::async, search);
    } catch (const std::system_error&) {  // no thread to be had: when awaited
      range = std::async(std::launch::deferred, search);
    }
  }
  const double tol = 1e-9 * std::max(1.0, std::abs(plan.current));
  // Awaits the valid range and checks the target against it (extended by
  // marching when beyond one step's range).
  const auto check_range = [&]() -> Status {
    const DeformPlan ranged = range.get();
    plan.valid_min = ranged.valid_min;
    plan.valid_max = ranged.valid_max;
    plan.limit_min = ranged.limit_min;
    plan.limit_max = ranged.limit_max;
    report.valid_min = plan.valid_min;
    report.valid_max = plan.valid_max;
    if (std::isnan(mo.target)) return Status::success();
    if (mo.target < plan.valid_min - tol || mo.target > plan.valid_max + tol) {
      const auto t = Clock::now();
      extend_valid_range(mesh, regions, plan, mo.target);
      report.seconds_range += seconds_since(t);
      report.valid_min = plan.valid_min;
      report.valid_max = plan.valid_max;
    }
    if (mo.target < plan.valid_min - tol || mo.target > plan.valid_max + tol) {
      std::ostringstream os;
      os << "TargetValue " << mo.target << " is outside the valid range " << range_text(plan) << " of this "
         << to_string(options.type) << " (now " << plan.current
         << "): beyond it a neighbouring face degenerates or the part intersects itself ("
         << (mo.target > plan.valid_max ? plan.limit_max : plan.limit_min) << ").";
      return Status::failure(os.str());
    }
    return Status::success();
  };
  // A failure before the range is known: the range's own message first
  // (a target beyond it often fails there too).
  const auto first_failure = [&](const Status& failure) -> Status {
    if (range.valid()) {
      const Status r = check_range();
      if (!r) return r;
    }
    return failure;
  };
  report.min_stretch_before = min_stretch(mesh);
  if (std::isnan(mo.target)) {
    // Measure only: the region a change would start from.
    report.deformable = extract_deformable_region(mesh, plan, 3 * mean_edge_length(mesh));
    report.min_stretch_after = report.min_stretch_before;
    check_range();
    report.seconds_total = seconds_since(start);
    return Status::success();
  }

  // The reference of the improvement: the mesh before the deformation.
  ReferenceMesh reference;
  if (mo.improve) {
    reference.points = mesh.points();
    for (index_t tt = 0; tt < mesh.tet_slots(); ++tt) {
      if (!mesh.tet_alive(tt)) continue;
      reference.tets.push_back(mesh.tet(tt));
      Tet fr;
      for (int f = 0; f < 4; ++f) fr[f] = mesh.face_region(tt, f);
      reference.face_regions.push_back(fr);
    }
    for (const SurfacePrimitive& sp : regions.surfaces) reference.region_types.push_back(sp.type);
    reference.geometry = make_boundary_geometry(regions.surfaces, {});
  }
  // Eq. 2.32 on the mesh before the change; the densities travel with the
  // material through every step (a new vertex takes its origin's, Eq. 2.33).
  double reference_edge = 0;
  const std::vector<double> reference_density =
      mo.improve ? vertex_density(reference.points, reference.tets, &reference_edge) : std::vector<double>();
  // The mean edge length (the reference's: the mesh before the change).
  const double h = mo.improve ? reference_edge : mean_edge_length(mesh);

  const double total = mo.target - plan.current;
  const double fraction = std::clamp(mo.max_step_fraction, 1.0 / mo.max_steps, 1.0);
  double step = total * fraction;
  double value = plan.current;
  // Per input tet: in the deformable region of some step.
  std::vector<std::uint8_t> input_region(mesh.tet_slots(), 0);
  std::vector<std::uint8_t> deformable;
  std::vector<Vec3> points;
  bool first = true;
  while (std::abs(mo.target - value) > tol) {
    if (!progress(std::abs(value - plan.current) / std::abs(total), "deforming")) {
      report.aborted = true;
      break;
    }
    if (!first) {
      graph = region_adjacency(mesh, regions.size());
      s = classify_surface_regions(mesh, regions, graph, options, plan);
      if (!s) return s;
      // Position has no dimension on the surfaces: the distance moved so far.
      if (options.type == DeformationType::Position) plan.current = value;
    }
    first = false;
    const double next = std::abs(mo.target - value) <= std::abs(step) + tol ? mo.target : value + step;
    const SurfaceUpdate update = update_region_surfaces(plan, regions, next);
    if (!update.error.empty())
      return first_failure(Status::failure("TargetValue " + std::to_string(next) + ": " + update.error + "."));
    auto t0 = Clock::now();
    const double reach = std::max(3 * h, 1.5 * largest_move(mesh, plan, update));
    deformable.clear();
    if (options.local_region) deformable = extract_deformable_region(mesh, plan, reach);
    VertexParameterization param;
    s = parameterize_vertices(mesh, plan, deformable, param);
    if (!s) return first_failure(s);
    report.seconds_parameterize += seconds_since(t0);
    t0 = Clock::now();
    reposition_vertices(mesh, regions, param, update, points);
    report.seconds_reposition += seconds_since(t0);
    std::string where;
    const std::size_t inverted = count_inverted(mesh, points, deformable, &where);
    if (range.valid()) {
      s = check_range();
      if (!s) return s;
    }
    const int steps_taken = report.steps + 1;
    const double remaining_steps = std::abs(mo.target - value) / std::abs(step);
    if (inverted > 0 && mo.improve && steps_taken + 2 * remaining_steps <= mo.max_steps) {
      step *= 0.5;  // smaller steps with improvement in between
      continue;
    }
    if (inverted > 0 && !mo.improve) {
      std::ostringstream os;
      os << "the change to " << next << " inverts " << inverted << " tetrahedra (centres " << where
         << "); turn Improve on (it takes the change in steps and repairs them) or take a smaller change.";
      return Status::failure(os.str());
    }
    report.inverted_before_improve += inverted;
    for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
      if (mesh.vertex_alive(v) && points[v] != mesh.point(v)) {
        mesh.set_point(v, points[v]);
        ++report.moved_vertices;
      }
    }
    for (index_t tt = 0; tt < static_cast<index_t>(deformable.size()); ++tt) {
      const index_t o = deformable[tt] && mesh.tet_alive(tt) ? mesh.tet_origin(tt) : kInvalidIndex;
      if (o >= 0 && o < static_cast<index_t>(input_region.size())) input_region[o] = 1;
    }
    regions.surfaces = update.surfaces;
    if (curves) refit_boundary_curves(mesh, regions.surfaces, plan, *curves);
    report.surface_unknowns += param.surfaces.unknowns.size() + param.curves.unknowns.size();
    report.inner_unknowns += param.inner.unknowns.size();
    if (mo.improve) {
      t0 = Clock::now();
      // The deformable region and one layer around it, per input tet (the
      // mask of phased_odt); the vertices of fixed regions frozen: they do
      // not move at all.
      std::vector<std::uint8_t> grown = deformable;
      if (!grown.empty()) {
        std::vector<std::uint8_t> touched(mesh.vertex_slots(), 0);
        for (index_t tt = 0; tt < mesh.tet_slots(); ++tt)
          if (mesh.tet_alive(tt) && grown[tt])
            for (const index_t v : mesh.tet(tt)) touched[v] = 1;
        for (index_t tt = 0; tt < mesh.tet_slots(); ++tt)
          if (mesh.tet_alive(tt) && !grown[tt])
            for (const index_t v : mesh.tet(tt)) grown[tt] |= touched[v];
      }
      std::vector<std::uint8_t> on_fixed(mesh.vertex_slots(), 0);
      for (index_t tt = 0; tt < mesh.tet_slots(); ++tt) {
        if (!mesh.tet_alive(tt)) continue;
        for (int f = 0; f < 4; ++f) {
          const index_t r = mesh.face_region(tt, f);
          if (mesh.is_boundary_face(tt, f) &&
              (r < 0 || r >= static_cast<index_t>(plan.roles.size()) || plan.roles[r] == RegionRole::Fixed))
            for (int k = 0; k < 3; ++k) on_fixed[mesh.tet(tt)[kTetFace[f][k]]] = 1;
        }
      }
      std::vector<std::uint8_t> mask(input_region.size(), 1);
      if (!grown.empty()) std::fill(mask.begin(), mask.end(), 0);
      for (index_t tt = 0; tt < mesh.tet_slots(); ++tt) {
        const index_t o = mesh.tet_alive(tt) ? mesh.tet_origin(tt) : kInvalidIndex;
        if (o >= 0 && o < static_cast<index_t>(mask.size()) && !grown.empty() && grown[tt]) mask[o] = 1;
      }
      const BoundaryGeometry geometry =
          make_boundary_geometry(regions.surfaces, curves ? *curves : std::vector<BoundaryCurve>());
      ImproveTargetOptions target_options;
      target_options.density = false;
      ImproveTarget target = make_improve_target(mesh, &geometry, &reference, target_options);
      std::vector<double> density(mesh.vertex_slots(), 0.0);
      for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
        if (!mesh.vertex_alive(v)) continue;
        const VertexStencil& origin = mesh.vertex_origin(v);
        for (int k = 0; k < 4; ++k) {
          const index_t o = origin.ids[k];
          if (o >= 0 && o < static_cast<index_t>(reference_density.size()))
            density[v] += origin.weights[k] * reference_density[o];
        }
      }
      // The density grid covers the tets the improvement may touch and one
      // layer more (it is read only there).
      std::vector<Tet> density_tets;
      if (grown.empty()) {
        density_tets = live_tet_list(mesh);
      } else {
        std::vector<std::uint8_t> near(mesh.vertex_slots(), 0);
        for (index_t tt = 0; tt < mesh.tet_slots(); ++tt)
          if (mesh.tet_alive(tt) && grown[tt])
            for (const index_t v : mesh.tet(tt)) near[v] = 1;
        for (index_t tt = 0; tt < mesh.tet_slots(); ++tt) {
          if (!mesh.tet_alive(tt)) continue;
          const Tet& T = mesh.tet(tt);
          if (near[T[0]] || near[T[1]] || near[T[2]] || near[T[3]]) density_tets.push_back(T);
        }
      }
      if (!target.density.build(mesh.points(), density_tets, density, 0.5 * reference_edge,
                                target_options.max_grid_points, false)) {
        target.warnings.push_back("no density field could be made; the improvement keeps no density target.");
      }
      for (const std::string& w : target.warnings) report.warnings.push_back(w);
      PhasedOdtOptions po;
      po.quality_floor = mo.quality_floor;
      po.tet_mask = std::move(mask);
      po.frozen_vertices = std::move(on_fixed);
      po.sort_min_tets = std::numeric_limits<std::size_t>::max();  // keep ids: the origin of each tet is tracked
      const PhasedOdtStats stats = phased_odt(mesh, geometry, target.view(), po);
      if (!stats.remaining_inverted.empty()) {
        std::ostringstream os;
        os << stats.remaining_inverted.size() << " tetrahedra stay inverted after the change to " << next
           << " and its improvement (centres";
        for (std::size_t i = 0; i < std::min<std::size_t>(3, stats.remaining_inverted.size()); ++i) {
          const Tet& T = mesh.tet(stats.remaining_inverted[i]);
          const Vec3 c = (mesh.point(T[0]) + mesh.point(T[1]) + mesh.point(T[2]) + mesh.point(T[3])) / 4;
          os << (i ? "; (" : " (") << c.x() << ", " << c.y() << ", " << c.z() << ")";
        }
        os << "); take a smaller change or a larger MaxSteps.";
        return Status::failure(os.str());
      }
      report.seconds_improve += seconds_since(t0);
    }
    value = next;
    ++report.steps;
  }
  if (range.valid()) {  // no step taken (aborted, or the target is the current value)
    const Status r = check_range();
    if (!r && !report.aborted) return r;
  }
  // The deformable region over all steps, per input tet.
  if (!options.local_region) std::fill(input_region.begin(), input_region.end(), 1);
  report.deformable = std::move(input_region);
  report.surfaces = regions.surfaces;
  report.min_stretch_after = min_stretch(mesh);
  report.seconds_total = seconds_since(start);
  return Status::success();
}

}  // namespace femorph
