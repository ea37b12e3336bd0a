// Phased ODT smoothing, thesis 2.6.1.2 (Fig. 2.34).
#include "improve/phased_odt.h"
#include "common/parallel.h"

#include "improve/control_mesh_density.h"
#include "improve/control_shape_accuracy.h"
#include "improve/flip_surface_edges.h"
#include "improve/odt_smooth_curves.h"
#include "improve/odt_smooth_surface.h"
#include "improve/improve_tets_by_flips.h"
#include "improve/improve_volume.h"
#include "improve/odt_smooth_volume.h"
#include "improve/optimize_worst_vertices.h"
#include "improve/split_locked_tets.h"
#include "improve/remove_degenerate_elements.h"
#include "improve/relax_edge_lengths.h"
#include "improve/remove_inverted_elements.h"
#include "mesh/tet_mesh.h"
#include "mesh/unique_edges.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <functional>
#include <chrono>
#include <memory>
#include <utility>

namespace femorph {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::size_t count_inverted(const TetMesh& mesh, std::vector<index_t>* ids = nullptr) {
  const index_t slots = mesh.tet_slots();
  const std::size_t n = parallel_reduce(
      slots, std::size_t(0),
      [&](long begin, long end, int) {
        std::size_t k = 0;
        for (long t = begin; t < end; ++t)
          k += mesh.tet_alive(static_cast<index_t>(t)) && mesh.orientation(static_cast<index_t>(t)) < 0;
        return k;
      },
      std::plus<std::size_t>());
  if (ids && n > 0)  // rare: listed serially, in id order
    for (index_t t = 0; t < slots; ++t)
      if (mesh.tet_alive(t) && mesh.orientation(t) < 0) ids->push_back(t);
  return n;
}

/// The live tets the density error is measured on: those of the region
/// (tet_mask, by origin) or all. Outside the region the density target is
/// not kept, and a whole-mesh pass would cost more than a local run.
std::vector<Tet> measured_tets(const TetMesh& mesh, const std::vector<std::uint8_t>& tet_mask) {
  if (tet_mask.empty()) return live_tet_list(mesh);
  std::vector<Tet> tets;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const index_t o = mesh.tet_origin(t);
    if (o >= 0 && static_cast<std::size_t>(o) < tet_mask.size() && tet_mask[o]) tets.push_back(mesh.tet(t));
  }
  return tets;
}

/// Vertices that may change: all of whose tets are flagged (a tet inherits
/// the flag of the input tet it comes from), and not on the boundary when it
/// is fixed, and not frozen. Empty: every vertex.
std::vector<std::uint8_t> movable_vertices(const TetMesh& mesh, const PhasedOdtOptions& options) {
  const std::vector<std::uint8_t>& tet_mask = options.tet_mask;
  const std::vector<std::uint8_t>& frozen = options.frozen_vertices;
  if (tet_mask.empty() && !options.fix_boundary && frozen.empty()) return {};
  std::vector<std::uint8_t> in(static_cast<std::size_t>(mesh.vertex_slots()), 0), out(in.size(), 0);
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const index_t o = mesh.tet_origin(t);
    const bool flagged =
        tet_mask.empty() || (o >= 0 && static_cast<std::size_t>(o) < tet_mask.size() && tet_mask[o]);
    for (const index_t v : mesh.tet(t)) (flagged ? in : out)[v] = 1;
  }
  for (std::size_t v = 0; v < in.size(); ++v)
    in[v] = in[v] && !out[v] && !(options.fix_boundary && mesh.on_boundary(static_cast<index_t>(v))) &&
            !(v < frozen.size() && frozen[v]);
  return in;
}

/// The vertices whose edges a phase's density control works on: curve and
/// corner vertices (phase 1), boundary vertices (phase 2), all (phase 3);
/// and movable.
std::vector<char> phase_vertices(const TetMesh& mesh, int phase, const std::vector<std::uint8_t>& movable) {
  std::vector<char> mask(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    if (!movable.empty() && !movable[v]) continue;
    const VertexClass c = mesh.vertex_class(v);
    mask[v] = phase == 2 || (phase == 1 && c != VertexClass::Inner) ||
              (phase == 0 && (c == VertexClass::Curve || c == VertexClass::Corner));
  }
  return mask;
}

/// Whether the mesh needs nothing (PhasedOdtOptions::skip_if_good): no
/// edge for the density control to split or collapse, every curved region
/// within its acceptable error. Quality and inversion are checked by the
/// caller.
bool needs_nothing(const TetMesh& mesh, const BoundaryGeometry& geometry, const PhasedOdtTarget& target,
                   const PhasedOdtOptions& options) {
  if (options.density_control && target.density && !target.density->empty())
    for (const Edge& e : unique_edges(mesh)) {
      const Vec3 &a = mesh.point(e.first), &b = mesh.point(e.second);
      const double scaled = (b - a).norm() * target.density->density_at(0.5 * (a + b), DensityLookup::Cell);
      if (scaled >= options.split_threshold || (scaled > 0 && scaled <= options.collapse_threshold)) return false;
    }
  if (options.accuracy_control && !target.acceptable_error.empty()) {
    const std::vector<double> error = region_geometric_error(mesh, geometry);
    for (std::size_t r = 0; r < error.size() && r < target.acceptable_error.size(); ++r)
      if (target.acceptable_error[r] > 0 && error[r] > target.acceptable_error[r]) return false;
  }
  return true;
}

void add_flips(PhasedOdtStats& stats, const FlipImproveReport& r) {
  stats.flips_23 += r.flips_23;
  stats.flips_32 += r.flips_32;
  stats.flips_44 += r.flips_44;
}

/// Live tets with stretch below `threshold` (in parallel: read only); with
/// `no_inner_vertex`, also how many of them have all four vertices on the
/// boundary. With `movable` (non-empty), only the tets with a movable vertex
/// count: no operation changes the others.
std::size_t count_below(const TetMesh& mesh, double threshold, std::size_t* no_inner_vertex = nullptr,
                        const std::vector<std::uint8_t>& movable = {}) {
  const auto may_change = [&](const Tet& T) {
    if (movable.empty()) return true;
    for (const index_t v : T)
      if (static_cast<std::size_t>(v) < movable.size() && movable[v]) return true;
    return false;
  };
  using Counts = std::pair<std::size_t, std::size_t>;  // (below, of which without inner vertex)
  const Counts c = parallel_reduce(
      static_cast<long>(mesh.tet_slots()), Counts(0, 0),
      [&](long begin, long end, int) {
        Counts k(0, 0);
        for (long t = begin; t < end; ++t) {
          if (!mesh.tet_alive(static_cast<index_t>(t))) continue;
          const Tet& T = mesh.tet(static_cast<index_t>(t));
          if (!may_change(T) ||
              !(tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3])) < threshold))
            continue;
          ++k.first;
          k.second += std::all_of(T.begin(), T.end(), [&](index_t v) { return mesh.on_boundary(v); });
        }
        return k;
      },
      [](Counts a, Counts b) { return Counts(a.first + b.first, a.second + b.second); });
  if (no_inner_vertex) *no_inner_vertex = c.second;
  return c.first;
}

/// Vertices of the tets with stretch below `threshold`, among the movable
/// ones (empty `movable`: all). The stretches in parallel, the marks after.
std::vector<std::uint8_t> vertices_of_poor_tets(const TetMesh& mesh, const std::vector<std::uint8_t>& movable,
                                                double threshold) {
  const long slots = mesh.tet_slots();
  std::vector<std::uint8_t> poor(static_cast<std::size_t>(slots), 0);
  const auto marks = [&](index_t v) {
    return movable.empty() || (static_cast<std::size_t>(v) < movable.size() && movable[v]);
  };
  parallel_for(slots, [&](long t) {
    if (!mesh.tet_alive(static_cast<index_t>(t))) return;
    const Tet& T = mesh.tet(static_cast<index_t>(t));
    poor[static_cast<std::size_t>(t)] =
        std::any_of(T.begin(), T.end(), marks) &&  // first: the cheaper test
        tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3])) < threshold;
  });
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (long t = 0; t < slots; ++t) {
    if (!poor[static_cast<std::size_t>(t)]) continue;
    for (const index_t v : mesh.tet(static_cast<index_t>(t))) mask[v] = marks(v);
  }
  return mask;
}

/// Curve and surface smoothing (odt_iterations sweeps) of the movable
/// vertices of the tets below the quality floor.
void smooth_boundary_near_poor_tets(TetMesh& mesh, const BoundaryGeometry& geometry, const PhasedOdtTarget& target,
                                    const PhasedOdtOptions& options, PhasedOdtStats& stats) {
  BoundarySmoothOptions bso;
  bso.iterations = options.odt_iterations;
  bso.vertex_mask = vertices_of_poor_tets(mesh, movable_vertices(mesh, options), options.quality_floor);
  bso.quality_floor = options.quality_floor;
  if (options.accuracy_control && !target.acceptable_error.empty()) bso.acceptable_error = &target.acceptable_error;
  if (options.smooth_curves) stats.moved_vertices += odt_smooth_curves(mesh, geometry, bso).moved;
  if (options.smooth_surfaces) stats.moved_vertices += odt_smooth_surface(mesh, geometry, bso).moved;
}

/// One round of volume smoothing (`iterations` ODT sweeps) and flips over
/// the vertices of `mask` (empty: all movable).
void smooth_volume_round(TetMesh& mesh, const PhasedOdtOptions& options, int iterations,
                         const std::vector<std::uint8_t>& mask, PhasedOdtStats& stats) {
  ImproveVolumeOptions ivo;
  ivo.rounds = 1;  // a second barely raises the minimum for its cost
  ivo.smooth.iterations = iterations;
  ivo.smooth.vertex_mask = mask;
  // Repairing the poor tets only: flips from them only, not from all tets
  // below 0.4 (faster, the same minimum).
  if (options.poor_elements_only) ivo.flips.quality_threshold = options.quality_floor;
  if (options.flips) {
    const ImproveVolumeStats vs = improve_volume(mesh, ivo);
    stats.moved_vertices += vs.moved;
    stats.flips_23 += vs.flips_23;
    stats.flips_32 += vs.flips_32;
    stats.flips_44 += vs.flips_44;
  } else {
    stats.moved_vertices += odt_smooth_volume(mesh, ivo.smooth).moved;
  }
}

/// The tets ODT leaves below the quality floor (next to the boundary, or in
/// a stretched region), in a few targeted passes while their number drops:
/// boundary smoothing near them, interior edges of tets locked on the
/// boundary split, inner vertices of the worst tets placed for their ball's
/// best minimum stretch, then any interior edge of them split, flips.
void repair_tets_below_floor(TetMesh& mesh, const BoundaryGeometry& geometry, const PhasedOdtTarget& target,
                             const PhasedOdtOptions& options, PhasedOdtStats& stats) {
  // The tets that may change (a local run leaves the rest as it is).
  std::size_t below = count_below(mesh, options.quality_floor, nullptr, movable_vertices(mesh, options));
  for (int pass = 0; pass < 4 && below > 0; ++pass) {
    if (pass > 0) smooth_boundary_near_poor_tets(mesh, geometry, target, options, stats);
    LockedTetOptions lo;
    lo.vertex_mask = movable_vertices(mesh, options);
    lo.threshold = options.quality_floor;
    stats.splits += split_locked_tets(mesh, lo).splits;
    WorstVertexOptions wo;
    wo.vertex_mask = movable_vertices(mesh, options);
    // Repairing the poor tets only: their vertices only (faster; the
    // minimum about the same).
    wo.threshold = options.poor_elements_only ? options.quality_floor : std::max(wo.threshold, options.quality_floor);
    stats.moved_vertices += optimize_worst_vertices(mesh, wo).improved;
    // From the second pass on, the tets still below the floor (inner
    // vertices or not): an interior edge split and its new vertex placed.
    if (pass > 0) {
      lo.only_locked = false;
      stats.splits += split_locked_tets(mesh, lo).splits;
    }
    if (options.flips) {
      FlipImproveOptions fo;
      fo.vertex_mask = wo.vertex_mask;
      if (options.poor_elements_only) fo.quality_threshold = options.quality_floor;
      add_flips(stats, improve_tets_by_flips(mesh, fo));
    }
    const std::size_t now = count_below(mesh, options.quality_floor, nullptr, movable_vertices(mesh, options));
    if (now >= below) break;
    below = now;
  }
}

/// Beyond the thesis, once the density has settled: curve and surface
/// smoothing again for the vertices of the tets still below the quality
/// floor, the accuracy control once more (the volume phase's collapses and
/// that smoothing reach the boundary), a round of volume smoothing over all
/// inner vertices (odt_iterations sweeps; with relax_edge_lengths one,
/// then the edge-length relaxation of the surface and the inner vertices)
/// and flips, and repair_tets_below_floor.
void finish_improvement(TetMesh& mesh, const BoundaryGeometry& geometry, const PhasedOdtTarget& target,
                        const PhasedOdtOptions& options, PhasedOdtStats& stats) {
  // The accuracy control (2.6.4) once more, under the quality floor.
  const auto accuracy = [&]() {
    if (!options.accuracy_control || target.acceptable_error.empty()) return;
    AccuracyControlOptions aco;
    aco.vertex_mask = movable_vertices(mesh, options);
    aco.min_stretch = options.quality_floor;
    const AccuracyControlStats as = control_shape_accuracy(mesh, geometry, target.acceptable_error, aco);
    stats.splits += as.splits;
    stats.accuracy_splits += as.splits;
  };
  accuracy();
  smooth_boundary_near_poor_tets(mesh, geometry, target, options, stats);
  accuracy();  // what is left beyond the error after the smoothing above
  const std::vector<std::uint8_t> movable = movable_vertices(mesh, options);
  const bool relax = options.relax_edge_lengths && target.density && !target.density->empty();
  smooth_volume_round(mesh, options, relax ? 1 : options.odt_iterations, movable, stats);
  if (relax) {
    RelaxEdgeLengthsOptions ro;
    ro.iterations = options.odt_iterations;
    ro.vertex_mask = movable;
    ro.quality_floor = options.quality_floor;
    if (options.accuracy_control && !target.acceptable_error.empty()) ro.acceptable_error = &target.acceptable_error;
    // The surface vertices first; one more inner sweep then takes up the
    // inner edges their moves changed (a lower density error and a higher
    // minimum stretch than without it).
    if (options.smooth_surfaces) {
      stats.moved_vertices += relax_surface_edge_lengths(mesh, geometry, *target.density, ro).moved;
      ++ro.iterations;
    }
    stats.moved_vertices += relax_edge_lengths(mesh, *target.density, ro).moved;
  }
  repair_tets_below_floor(mesh, geometry, target, options, stats);
}

}  // namespace

PhasedOdtStats phased_odt(TetMesh& mesh, const BoundaryGeometry& given_geometry, const PhasedOdtTarget& target,
                          const PhasedOdtOptions& options) {
  const auto start = Clock::now();
  BoundaryGeometry geometry = given_geometry;  // the kept triangles are added below
  PhasedOdtStats stats;
  live_stretch_range(mesh, &stats.min_stretch_before, &stats.mean_stretch_before);
  stats.tets_before = mesh.live_tets();
  stats.inverted_before = count_inverted(mesh);
  const bool density = options.density_control && target.density && !target.density->empty();
  if (target.density && !target.density->empty())
    stats.density_error_before =
        mean_density_error(mesh.points(), measured_tets(mesh, options.tet_mask), *target.density, DensityLookup::Cell);

  // New and moved boundary vertices go onto their fitted surface or curve
  // (2.6.1.3); corners and vertices of unknown regions keep the position given.
  const ProjectVertexFn project = [&mesh, &geometry](index_t v, const Vec3& p) {
    const VertexConstraint c = vertex_constraint(mesh, geometry, v);
    Vec3 q;
    if ((c.kind == VertexConstraint::Surface || c.kind == VertexConstraint::Curve ||
         c.kind == VertexConstraint::Discrete) &&
        project_to_constraint(c, p, &q))
      return q;
    return p;
  };
  const auto report = [&](double fraction, const char* phase) {
    if (stats.aborted) return false;
    if (options.progress && !options.progress(fraction, phase)) stats.aborted = true;
    return !stats.aborted;
  };
  using Step = PhasedOdtStats::Step;
  double trace_seconds = 0;  // spent on the quality trace
  // PhasedOdtOptions::trace_quality: the minimum stretch now, stamped with
  // the time without the tracing.
  const auto trace = [&]() {
    if (!options.trace_quality) return;
    const Clock::time_point t0 = Clock::now();
    const double at = std::chrono::duration<double>(t0 - start).count() - trace_seconds;
    double min = 0, mean = 0;
    live_stretch_range(mesh, &min, &mean);
    stats.quality_trace.push_back({at, min});
    trace_seconds += seconds_since(t0);
  };
  // Time of one step from `t0` on (then the trace); returns now.
  const auto lap = [&](Step step, Clock::time_point t0) {
    stats.step_seconds[step] += std::chrono::duration<double>(Clock::now() - t0).count();
    trace();
    return Clock::now();
  };
  trace();
  const auto remove_inverted = [&]() {
    InvertedRemovalOptions io;
    io.project = project;
    const InvertedRemovalStats is = remove_inverted_elements(mesh, io);
    stats.removed_inverted += is.initial_inverted - is.remaining_inverted;
  };
  // Fig. 2.34 (B): slivers, caps and spades among the vertices of `mask`
  // (`touched`: the vertices changed, when given).
  const auto remove_degenerate = [&](std::vector<std::uint8_t> mask, std::vector<char>* touched) {
    DegenerateRemovalOptions dro;
    dro.stretch_threshold = options.degenerate_threshold;
    dro.project = project;
    dro.vertex_mask = std::move(mask);
    dro.touched = touched;
    const DegenerateRemovalStats ds = remove_degenerate_elements(mesh, dro);
    stats.removed_slivers += ds.removed_slivers;
    stats.removed_caps += ds.removed_caps;
    stats.removed_spades += ds.removed_spades;
  };

  if (options.skip_if_good && stats.inverted_before == 0 && stats.min_stretch_before >= options.quality_floor &&
      (options.poor_elements_only || needs_nothing(mesh, geometry, target, options))) {
    stats.skipped = true;
    stats.min_stretch_after = stats.min_stretch_before;
    stats.mean_stretch_after = stats.mean_stretch_before;
    stats.tets_after = stats.tets_before;
    stats.density_error_after = stats.density_error_before;
    stats.geometric_error_after = region_geometric_error(mesh, geometry);
    stats.seconds = seconds_since(start);
    return stats;
  }

  // PhasedOdtOptions::keep_minimum: the input, to give back if the result's
  // minimum falls below the bound (an unrepaired inverted input has a
  // negative minimum, which no result falls below: no copy needed).
  const double keep_bound = options.keep_input_minimum
                                ? stats.min_stretch_before
                                : std::min(stats.min_stretch_before, options.quality_floor);
  std::unique_ptr<TetMesh> input_copy;
  if (options.keep_minimum && stats.inverted_before == 0 && keep_bound > 0)
    input_copy = std::make_unique<TetMesh>(mesh);

  if (options.move_unfitted_regions && !options.fix_boundary) add_discrete_regions(mesh, geometry);

  // Fig. 2.34 (B) first for inverted tets: every later step needs a valid mesh.
  if (options.remove_inverted && stats.inverted_before > 0) {
    const Clock::time_point t0 = Clock::now();
    remove_inverted();
    lap(Step::Removal, t0);
  }

  static const char* const kPhaseNames[3] = {"boundary curves", "surface triangles", "tetrahedra"};
  const bool enabled[3] = {options.smooth_curves, options.smooth_surfaces, options.smooth_volume};
  if (options.poor_elements_only && report(0.0, "poor elements")) {
    const auto phase_start = Clock::now();
    Clock::time_point t = phase_start;
    if (options.remove_degenerate) remove_degenerate(movable_vertices(mesh, options), nullptr);
    if (options.remove_inverted && count_inverted(mesh) > 0) remove_inverted();
    t = lap(Step::Removal, t);
    if (report(0.2, "poor elements")) {
      smooth_boundary_near_poor_tets(mesh, geometry, target, options, stats);
      // One ODT sweep: the passes after it place these vertices one by one
      // (more sweeps took longer for no better minimum).
      if (options.smooth_volume)
        smooth_volume_round(mesh, options, 1,
                            vertices_of_poor_tets(mesh, movable_vertices(mesh, options), options.quality_floor),
                            stats);
      t = lap(Step::Smoothing, t);
    }
    if (report(0.5, "poor elements")) {
      repair_tets_below_floor(mesh, geometry, target, options, stats);
      lap(Step::Finishing, t);
    }
    stats.phase_seconds[2] = seconds_since(phase_start);
  }
  for (int phase = 0; phase < 3 && !options.poor_elements_only; ++phase) {
    if (!enabled[phase]) continue;
    const auto phase_start = Clock::now();
    std::size_t last_operations = static_cast<std::size_t>(-1);
    for (int loop = 0; loop < std::max(1, options.max_loops); ++loop) {
      if (!report((phase + static_cast<double>(loop) / std::max(1, options.max_loops)) / 3.0, kPhaseNames[phase]))
        break;
      ++stats.loops[phase];
      const std::vector<std::uint8_t> movable = movable_vertices(mesh, options);
      Clock::time_point t = Clock::now();

      // (B) degenerated and inverted element removal (2.6.2).
      std::vector<char> touched;  // by this loop's operations (boundary phases)
      bool inverted_removed = false;  // not marked in `touched`
      if (options.remove_degenerate) remove_degenerate(movable, phase < 2 ? &touched : nullptr);
      if (options.remove_inverted && count_inverted(mesh) > 0) {
        remove_inverted();
        inverted_removed = true;
      }
      t = lap(Step::Removal, t);

      // (C) mesh density control (2.6.3), one split and one collapse pass
      // per loop, on the edges of this phase.
      std::size_t operations = 0;
      if (density) {
        DensityControlOptions dco;
        dco.split_threshold = options.split_threshold;
        dco.collapse_threshold = options.collapse_threshold;
        dco.min_stretch = options.degenerate_threshold;
        dco.max_iterations = 1;
        dco.measure_error = false;
        dco.project = project;
        dco.project_in_parallel = true;  // vertex_constraint and the projections are thread safe
        // Beyond the thesis: a boundary collapse may not lengthen a chord
        // past its region's acceptable error (2.6.4).
        if (options.accuracy_control && !target.acceptable_error.empty())
          dco.accept_boundary_collapse = [&](index_t keep, index_t remove, const Vec3& x,
                                             const std::vector<index_t>& ball_keep,
                                             const std::vector<index_t>& ball_remove) {
            return collapse_chords_within_error(mesh, geometry, target.acceptable_error, keep, remove, x, ball_keep,
                                                ball_remove);
          };
        dco.vertex_mask = phase_vertices(mesh, phase, movable);
        dco.split_inner_edges = options.split_inner_edges && phase == 2;
        if (phase < 2) dco.touched = &touched;
        const DensityControlStats dcs = control_mesh_density(mesh, *target.density, dco);
        stats.splits += dcs.splits;
        stats.collapses += dcs.collapses;
        operations += dcs.splits + dcs.collapses;
        // Beyond the thesis: the splits and collapses scatter neighbours over
        // memory (new tets fill freed slots anywhere); renumbered along
        // space, the steps after them walk the mesh faster.
        if (phase == 2 && dcs.splits + dcs.collapses > 0 && mesh.live_tets() >= options.sort_min_tets)
          mesh.sort_spatially();
        t = lap(Step::Density, t);
      }
      // (C) shape approximation accuracy control (2.6.4), on the boundary
      // (in every phase: the density control of phase 3 collapses boundary
      // edges too).
      if (options.accuracy_control && !target.acceptable_error.empty()) {
        AccuracyControlOptions aco;
        aco.vertex_mask = movable_vertices(mesh, options);
        aco.min_stretch = options.quality_floor;
        if (phase < 2) aco.touched = &touched;
        const AccuracyControlStats as = control_shape_accuracy(mesh, geometry, target.acceptable_error, aco);
        stats.splits += as.splits;
        stats.accuracy_splits += as.splits;
        operations += as.splits;
        t = lap(Step::Accuracy, t);
      }

      // Fig. 2.34: the loop ends when no density or accuracy operation is
      // left (and, beyond the thesis, when they stall or are few:
      // min_operation_fraction).
      const bool last_loop = operations == 0 || operations >= last_operations ||
                             static_cast<double>(operations) <
                                 options.min_operation_fraction * static_cast<double>(mesh.live_tets());

      // (A) ODT smoothing of this phase's elements (2.6.5), then its flips.
      const std::vector<std::uint8_t> smooth_mask = movable_vertices(mesh, options);
      if (phase < 2) {
        BoundarySmoothOptions bso;
        bso.iterations = options.odt_iterations;
        bso.vertex_mask = smooth_mask;
        // Beyond the thesis: a last loop after the first smooths only where
        // its few operations (below min_operation_fraction of the tets)
        // changed the mesh; the loop before smoothed the rest.
        // The removal (B), density and accuracy operations mark where; the
        // inverted element removal does not, so after it all are smoothed.
        if (last_loop && loop > 0 && !inverted_removed) {
          bso.vertex_mask.assign(static_cast<std::size_t>(mesh.vertex_slots()), 0);
          for (std::size_t v = 0; v < bso.vertex_mask.size(); ++v)
            bso.vertex_mask[v] = v < touched.size() && touched[v] &&
                                 (smooth_mask.empty() || (v < smooth_mask.size() && smooth_mask[v]));
        }
        bso.quality_floor = options.quality_floor;
        if (options.accuracy_control && !target.acceptable_error.empty()) bso.acceptable_error = &target.acceptable_error;
        const OdtSmoothReport r =
            phase == 0 ? odt_smooth_curves(mesh, geometry, bso) : odt_smooth_surface(mesh, geometry, bso);
        stats.moved_vertices += r.moved;
        t = lap(Step::Smoothing, t);
        if (phase == 1 && options.flips) {
          SurfaceFlipOptions sfo;
          sfo.vertex_mask = smooth_mask;
          sfo.min_stretch = options.quality_floor;
          stats.surface_flips += flip_surface_edges(mesh, geometry, sfo).flips;
          t = lap(Step::Flips, t);
        }
      } else {
        OdtSmoothOptions oso;
        oso.iterations = 1;  // the finishing step sweeps odt_iterations times
        // Beyond the thesis: inside the loop only the vertices of the tets
        // below 0.5 (and their neighbours through those tets) are smoothed;
        // the finishing step sweeps all of them, right after the last loop,
        // which therefore leaves them to it.
        if (!last_loop) {
          oso.vertex_mask = vertices_of_poor_tets(mesh, smooth_mask, 0.5);
          stats.moved_vertices += odt_smooth_volume(mesh, oso).moved;
          t = lap(Step::Smoothing, t);
        }
        if (options.flips) {
          FlipImproveOptions fo;
          fo.vertex_mask = smooth_mask;
          add_flips(stats, improve_tets_by_flips(mesh, fo));
          t = lap(Step::Flips, t);
        }
      }
      if (last_loop) break;
      last_operations = operations;
    }
    if (phase == 2 && !stats.aborted && report(0.95, kPhaseNames[2])) {
      const Clock::time_point t0 = Clock::now();
      finish_improvement(mesh, geometry, target, options, stats);
      lap(Step::Finishing, t0);
    }
    stats.phase_seconds[phase] = seconds_since(phase_start);
    if (stats.aborted) break;
  }

  live_stretch_range(mesh, &stats.min_stretch_after, &stats.mean_stretch_after);
  if (input_copy && !stats.aborted && stats.min_stretch_after < keep_bound) {
    stats.kept_input = true;
    stats.min_stretch_rejected = stats.min_stretch_after;
    mesh = std::move(*input_copy);
    stats.min_stretch_after = stats.min_stretch_before;
    stats.mean_stretch_after = stats.mean_stretch_before;
  }
  input_copy.reset();
  stats.tets_after = mesh.live_tets();
  stats.below_floor = count_below(mesh, options.quality_floor, &stats.below_floor_on_boundary);
  count_inverted(mesh, &stats.remaining_inverted);
  if (target.density && !target.density->empty())
    stats.density_error_after =
        mean_density_error(mesh.points(), measured_tets(mesh, options.tet_mask), *target.density, DensityLookup::Cell);
  stats.geometric_error_after = region_geometric_error(mesh, geometry);
  stats.seconds = seconds_since(start) - trace_seconds;
  return stats;
}

}  // namespace femorph
