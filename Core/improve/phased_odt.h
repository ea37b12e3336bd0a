// Phased ODT smoothing, the quality improvement method of thesis 2.6
// (Fig. 2.34): the modified ODT loop -- degenerated and inverted element
// removal, mesh density control, shape approximation accuracy control, ODT
// smoothing -- run on the boundary curves, the surface triangles and the
// tetrahedra, in that order, each phase repeated until no density or accuracy
// operation is left.
#pragma once

#include "common/types.h"
#include "improve/boundary_geometry.h"
#include "improve/control_shape_accuracy.h"
#include "improve/mesh_density.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace femorph {

class TetMesh;

struct PhasedOdtOptions {
  /// Phases of Fig. 2.34 (A).
  bool smooth_curves = true;
  bool smooth_surfaces = true;
  bool smooth_volume = true;
  /// Steps of the modified ODT loop (Fig. 2.34 (B), (C)).
  bool remove_degenerate = true;
  bool remove_inverted = true;
  bool density_control = true;
  bool accuracy_control = true;
  /// Flips 2-3 / 3-2 / 4-4 in the volume phase and surface edge flips
  /// (Fig. 2.45) in the surface phase.
  bool flips = true;
  /// Beyond the thesis: the finishing round ends with odt_iterations sweeps
  /// of relax_surface_edge_lengths (with smooth_surfaces) and one more of
  /// relax_edge_lengths (edges pulled toward 1 / rho_GC), after one ODT
  /// sweep instead of odt_iterations: the ODT sweeps leave the density
  /// error (Eq. 2.35) above its goal, the relaxation brings it down and
  /// raises the mean stretch. Only with a density target.
  bool relax_edge_lengths = true;
  /// ODT sweeps per step of the loop (thesis: "two or three times"). 2: a
  /// third barely changes the minimum and mean stretch for its cost.
  int odt_iterations = 2;
  /// Repetitions of the modified ODT loop per phase at most.
  int max_loops = 8;
  /// Beyond the thesis: a phase's loop also ends when its density and
  /// accuracy operations stop decreasing or touch fewer than this fraction
  /// of the tets (ODT smoothing keeps nudging edge lengths across the
  /// thresholds, and the last loops cost much for little). 0: the thesis'
  /// rule, until none is left.
  double min_operation_fraction = 0.05;
  /// Beyond the thesis: the volume phase renumbers the mesh along space
  /// (TetMesh::sort_spatially) after each density control that changed it,
  /// from this many live tets on (below it the mesh fits in cache). Vertex
  /// and tet ids do not survive phased_odt then.
  std::size_t sort_min_tets = 100000;
  /// Mesh density thresholds beta1, beta2 (2.6.3).
  double split_threshold = 1.5;
  double collapse_threshold = 0.67;
  /// gamma_st, stretch below which a tet is degenerated (2.6.2).
  double degenerate_threshold = 0.05;
  /// Beyond the thesis: the boundary steps (accuracy splits, surface flips,
  /// curve and surface smoothing) may not make a tet below this stretch
  /// that is also worse than the worst tet they replace; their vertices stay
  /// on the boundary, where the volume phase cannot repair them. The tets
  /// below it are what the finishing passes (and poor_elements_only
  /// throughout) repair. The filter's QualityFloor.
  double quality_floor = 0.3;
  /// Beyond the thesis: repair only the poor tets and leave the rest of the
  /// mesh as it is, as Gmsh's and TetGen's optimizers do. Inverted and
  /// degenerated tets are removed (2.6.2), then the vertices of the tets
  /// below quality_floor are smoothed (curves and surfaces odt_iterations
  /// sweeps, volume one, with flips) and repair_tets_below_floor's passes
  /// run (vertex placement and flips for the tets below the floor only).
  /// No density or accuracy control and no sweep over the whole mesh:
  /// faster than the phases, but a stretched region keeps its stretched
  /// edges and a lower minimum (Testing/Benchmarks/RESULTS.md). Tets away
  /// from those below the floor and their neighbours stay as they are.
  bool poor_elements_only = false;
  /// Restriction to a region (Deform, Adapt): one flag per tet slot; only
  /// vertices all of whose tets are flagged move, and only edges between such
  /// vertices are split, collapsed or flipped. Empty: the whole mesh.
  std::vector<std::uint8_t> tet_mask;
  /// Vertices (by slot) that must stay exactly where they are, with their
  /// edges (Deform's fixed regions). Empty: none.
  std::vector<std::uint8_t> frozen_vertices;
  /// Leave a mesh that needs nothing as it is, unchanged and fast (an
  /// acceptance case of Improve, docs/ARCHITECTURE.md): no inverted tet,
  /// every tet at or above quality_floor, no edge beyond the density
  /// thresholds and every curved region within its acceptable error. Off:
  /// always run the phases.
  bool skip_if_good = true;
  /// Beyond the thesis: the result's minimum stretch may never
  /// fall below min(the input's minimum, quality_floor). A run that ends
  /// below it gives the input back unchanged (PhasedOdtStats::kept_input);
  /// the phases work on the mesh, a copy of the input is kept for this
  /// (one copy of the mesh's arrays, taken only when the phases run).
  bool keep_minimum = true;
  /// With keep_minimum: the bound is the input's minimum itself, whatever
  /// the floor. For a density target that is the input's own (Improve
  /// without a Reference): a mesh already at its own density has nothing
  /// to gain that a lower minimum would pay for (a perfect lattice of 48
  /// tets came out with 84 and a lower minimum).
  bool keep_input_minimum = false;
  /// For benchmarks: the minimum stretch over the live tets after every step
  /// goes into PhasedOdtStats::quality_trace (one parallel pass over the
  /// tets per step, left out of the trace's and the steps' times).
  bool trace_quality = false;
  /// Keep every boundary vertex where it is (no segmentation): only inner
  /// vertices move, only edges between inner vertices are split or
  /// collapsed. Inverted tets are still repaired, which may remove a
  /// boundary vertex.
  bool fix_boundary = false;
  /// Beyond the thesis: the density control of the volume phase also splits
  /// long inner edges between fixed or frozen vertices (never a boundary
  /// edge): a region whose boundary holds still keeps its density where the
  /// edges from that boundary stretch (Adapt, behind a moving object).
  bool split_inner_edges = false;
  /// Beyond the thesis: the surface vertices of a region without a fit (a
  /// stretched fillet, a free-form face) move on that region's triangles as
  /// given (add_discrete_regions) instead of staying where they are.
  bool move_unfitted_regions = true;
  /// Progress in [0, 1] with the phase's name; return false to abort (the
  /// mesh is then valid but only partly improved).
  std::function<bool(double fraction, const char* phase)> progress;
};

/// What the improvement aims at, from the reference mesh (before the
/// deformation).
struct PhasedOdtTarget {
  /// Target mesh density field (Eq. 2.33). Null: no density control.
  const DensityGrid* density = nullptr;
  /// Acceptable geometric error per region id (2.6.4): the largest distance
  /// of a surface edge's midpoint to the fitted surface in the reference.
  /// Empty, or NaN / <= 0 for a region: no accuracy control there.
  std::vector<double> acceptable_error;
};

struct PhasedOdtStats {
  double min_stretch_before = 0, mean_stretch_before = 0;
  double min_stretch_after = 0, mean_stretch_after = 0;
  std::size_t tets_before = 0, tets_after = 0;
  std::size_t inverted_before = 0;
  /// When a density target is given; over the tets of tet_mask when set.
  DensityError density_error_before, density_error_after;
  /// Largest geometric error (2.6.4) per region id after; NaN for regions
  /// without a curved fit.
  std::vector<double> geometric_error_after;
  std::size_t splits = 0, collapses = 0;          ///< density and accuracy control
  std::size_t accuracy_splits = 0;                ///< of which for accuracy
  std::size_t flips_23 = 0, flips_32 = 0, flips_44 = 0, surface_flips = 0;
  std::size_t removed_slivers = 0, removed_caps = 0, removed_spades = 0;
  std::size_t removed_inverted = 0;               ///< inverted tets repaired
  std::size_t moved_vertices = 0;                 ///< accepted ODT moves
  /// Tets left below quality_floor after, and how many of them have all
  /// four vertices on the boundary: no inner vertex to move, so their shape
  /// is that of the boundary triangles (a face narrower than the mesh, as a
  /// strip between two curves); only a finer boundary mesh there helps.
  std::size_t below_floor = 0, below_floor_on_boundary = 0;
  /// Inverted tets no operation could repair (tet slot ids after the run).
  std::vector<index_t> remaining_inverted;
  std::array<int, 3> loops{{0, 0, 0}};            ///< modified ODT loops per phase
  std::array<double, 3> phase_seconds{{0, 0, 0}}; ///< curves, surfaces, volume
  /// The same time by step, over all phases: degenerate and inverted
  /// removal, density control, accuracy control, ODT smoothing, flips, the
  /// finishing step of the volume phase (indexed by Step, named kStepNames).
  enum Step { Removal, Density, Accuracy, Smoothing, Flips, Finishing, kSteps };
  static constexpr const char* kStepNames[kSteps] = {"Removal", "Density", "Accuracy", "Smoothing", "Flips",
                                                     "Finishing"};
  std::array<double, kSteps> step_seconds{};
  /// With PhasedOdtOptions::trace_quality: (seconds since the start, minimum
  /// stretch) at the start and after every step, in order.
  std::vector<std::array<double, 2>> quality_trace;
  double seconds = 0;
  bool aborted = false;
  bool skipped = false;  ///< the mesh needed nothing (skip_if_good)
  /// The result fell below the keep_minimum bound; the mesh is the input as
  /// given, and min_stretch_rejected the minimum of the result dropped.
  bool kept_input = false;
  double min_stretch_rejected = 0;
};

/// Thesis Fig. 2.34 on `mesh` (built with BuildOptions::allow_inverted when it
/// may hold inverted tets). Boundary vertices stay on their constraint
/// (vertex_constraint()); vertices of unknown regions and corners stay put.
/// The mesh stays valid throughout; inverted tets of the input are removed
/// first. Deterministic.
PhasedOdtStats phased_odt(TetMesh& mesh, const BoundaryGeometry& geometry, const PhasedOdtTarget& target,
                          const PhasedOdtOptions& options = {});

}  // namespace femorph
