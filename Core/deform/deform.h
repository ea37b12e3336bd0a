// Dimension-driven shape deformation of a tetrahedral mesh (thesis 2.5): a
// CAD dimension (a distance, a radius, a chamfer, a position) changed on the
// mesh itself by moving its vertices, the boundary onto the updated analytic
// surfaces and the inside by mean value coordinates (space embedding).
//
// Steps, one file each: region_adjacency (the region graph), classify_surface_regions
// (2.5.2), measure_dimension and update_region_surfaces (Table 2.7),
// extract_deformable_region (2.5.3), mean_value_coordinates (Eqs. 2.11-2.20),
// parameterize_vertices and reposition_vertices (2.5.4), find_valid_range,
// and deform_mesh, which chains them with Improve (2.6) in between steps.
#pragma once

#include "common/types.h"
#include "geometry/surface_primitive.h"
#include "mesh/tet_mesh.h"
#include "mesh/surface_mesh.h"
#include "segment/segmentation.h"

#include <Eigen/SparseCore>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace femorph {

/// Table 2.7, in its order (the filter's DeformationType enumeration).
enum class DeformationType : std::int32_t {
  Distance = 0,        ///< (1) between two parallel planes: boss height, hole depth, a width
  CylinderRadius = 1,  ///< (2) radius of a cylindrical boss or hole
  FilletRadius = 2,    ///< (3) minor radius of a cylindrical or toroidal fillet
  ChamferAngle = 3,    ///< (4) angle between a chamfer (or taper) and its reference face, degrees
  ChamferLength = 4,   ///< (5) chamfer distance along the reference face
  SphereRadius = 5,    ///< (6) radius of a spherical face (centre kept)
  Position = 6,        ///< (7) position of a local object (boss, rib, hole) on its plane(s)
};
const char* to_string(DeformationType type);

/// Role of a surface region (2.5.2, Figs. 2.20-2.21).
enum class RegionRole : std::int8_t { Fixed = 0, Control = 1, Following = 2, Deformed = 3 };
const char* to_string(RegionRole role);

/// The segmentation as Deform reads it: per region id its fitted surface
/// (type Unknown: none) and convexity; regions are the ids of
/// TetMesh::face_region.
struct DeformRegions {
  std::vector<SurfacePrimitive> surfaces;
  std::vector<Convexity> convexity;
  std::size_t size() const { return surfaces.size(); }
};

/// Region adjacency over the boundary of a mesh: neighbours, whether they
/// meet tangentially (G1), and areas.
struct RegionGraph {
  std::vector<std::vector<index_t>> neighbors;  ///< ascending
  std::vector<std::vector<bool>> g1;            ///< per neighbour
  std::vector<double> area;
  bool adjacent(index_t a, index_t b) const;
  bool tangent(index_t a, index_t b) const;
};

/// Neighbours from the boundary edges; G1 when the mean angle between the
/// two regions' triangle normals along their shared edges is below
/// `g1_angle_deg`.
RegionGraph region_adjacency(const TetMesh& mesh, std::size_t region_count, double g1_angle_deg = 12.0);

struct DeformOptions {
  DeformationType type = DeformationType::Distance;
  index_t control_region = kInvalidIndex;
  /// Distance: the opposite parallel plane; ChamferAngle/ChamferLength: the
  /// face the angle and the length are measured on; Position: the plane(s)
  /// the object sits on. Empty: chosen automatically (DeformPlan::reference).
  std::vector<index_t> reference_regions;
  /// Replaces the automatic following regions when set (2.5.2, last step).
  bool override_following = false;
  std::vector<index_t> following_regions;
  /// Position: the translation (world coordinates, in the reference plane).
  Vec3 translation = Vec3::Zero();
  /// Planes and cones next to the control region whose area is below this
  /// fraction of the control region's, and inclined to it, follow it as
  /// chamfers (2.5.2).
  double chamfer_area_ratio = 1.0;
  /// Two radii are equal (equal-radius sphere corners) within this fraction.
  double radius_tolerance = 0.02;
  /// Restrict the inner repositioning to the deformable region (2.5.3).
  /// Off: every inner vertex of the mesh is repositioned.
  bool local_region = true;
};

/// Classification and measurement (2.5.2, 2.5.3), independent of the target.
struct DeformPlan {
  DeformOptions options;
  std::vector<RegionRole> roles;         ///< per region
  std::vector<index_t> reference;        ///< the reference regions used
  std::vector<index_t> moved;            ///< control and following regions
  double current = std::numeric_limits<double>::quiet_NaN();  ///< the dimension now
  double valid_min = std::numeric_limits<double>::quiet_NaN();
  double valid_max = std::numeric_limits<double>::quiet_NaN();
  /// What limits the range at each end (a surface that would not exist, a
  /// boundary triangle that would fold and where); empty when capped.
  std::string limit_min, limit_max;
  /// Geometry of the feature that update_region_surfaces uses (frames,
  /// profile lines, the neighbours each fillet is tangent to).
  struct Feature;
  std::shared_ptr<const Feature> feature;
  double part_size = 0;  ///< bounding-box diagonal
  /// The inside of the moved regions follows their boundary by 2D mean
  /// value coordinates, then onto the updated surface (2.5.4.5, step 3):
  /// where a boundary curve slides along a deformed neighbour (a sphere's
  /// rim along its cone, a shaft's end along a taper) a map of every vertex
  /// would leave the ring next to it outside the new region. Off: every
  /// moved vertex is mapped (Method 1).
  bool solve_moved_interior = true;
};

/// 2.5.2: roles of every region for `options`, the reference regions and the
/// current dimension; fails with a message naming the problem (a control
/// region of the wrong type for the deformation type, no parallel reference
/// plane...).
Status classify_surface_regions(const TetMesh& mesh, const DeformRegions& regions, const RegionGraph& graph,
                                const DeformOptions& options, DeformPlan& plan);

/// The dimension the plan controls, measured on `surfaces` (Table 2.7).
double measure_dimension(const DeformPlan& plan, const std::vector<SurfacePrimitive>& surfaces);

/// How the moved regions map to their updated surfaces for one value.
struct SurfaceUpdate {
  std::vector<SurfacePrimitive> surfaces;  ///< every region, the moved ones updated
  /// Maps a point of moved region r (an id of plan.moved) onto its updated
  /// surface, keeping its place on the feature (Method 1 of 2.5.4.1).
  std::function<Vec3(index_t region, const Vec3& p)> map;
  std::string error;  ///< non-empty: the value makes no valid geometry (why)
};

/// Table 2.7, third column: the surfaces of the control and following
/// regions for dimension `value` (for Position, the fraction of the
/// translation).
SurfaceUpdate update_region_surfaces(const DeformPlan& plan, const DeformRegions& regions, double value);

/// Mean value coordinates of point x with respect to the fan of triangles
/// (x, ring[k], ring[k + 1]) on a surface (Floater 2003, Eqs. 2.11-2.12,
/// with the fan's own angles as the development of the surface): `fan` holds
/// (a, b) pairs of the triangles around x; weights per distinct vertex of
/// `vertices` (same order), normalised.
void mean_value_coordinates_2d(const Vec3& x, const std::vector<Vec3>& vertices,
                               const std::vector<std::array<int, 2>>& fan, std::vector<double>& weights);

/// Mean value coordinates of point x inside a closed triangle mesh (Ju et
/// al. 2005, Eqs. 2.13-2.20): triangles index `vertices`, oriented outward.
/// Returns false when x lies on the mesh (the weights are then its
/// barycentric ones).
bool mean_value_coordinates_3d(const Vec3& x, const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles,
                               std::vector<double>& weights);

/// The 3D mean value coordinates of vertex v in its 1-ring polyhedron (the
/// link of its ball, Eq. 2.10's handle vertices; thesis 3.5.3's Eq. 3.1):
/// `ids` the ring's vertices, `weights` theirs. For inner vertices; safe
/// from several threads at once while the mesh does not change.
void vertex_ring_mvc(const TetMesh& mesh, index_t v, std::vector<index_t>& ids, std::vector<double>& weights);

/// The deformable region (2.5.3): per tet slot 1 when the deformation may
/// move its vertices: the tets of the vertices nearer (along the mesh's
/// edges) to a moved region than to every fixed one or within `reach` of a
/// moved region, and one layer around them, expanded while it has few inner
/// vertices.
std::vector<std::uint8_t> extract_deformable_region(const TetMesh& mesh, const DeformPlan& plan, double reach);

/// The parameterisation of 2.5.4.3: which vertices are fixed, mapped or
/// solved, their coordinates and the factorised systems (Eq. 2.10). Built
/// once; reposition_vertices then costs one map and up to three solves per
/// target (none where a RepositionHistory spans the change).
struct VertexParameterization {
  enum Kind : std::uint8_t { Fixed = 0, Mapped = 1, Curve = 2, Surface = 3, Inner = 4 };
  std::vector<Kind> kind;                 ///< per vertex slot
  std::vector<index_t> region;            ///< Mapped: the moved region; Surface: its region
  std::vector<std::array<index_t, 2>> curve_regions;  ///< Curve and Mapped on a curve: the two regions
  std::vector<std::vector<index_t>> mapped_regions;   ///< Mapped: every region of the vertex
  std::vector<index_t> mapped;            ///< the Mapped vertices
  std::vector<index_t> moving_tets;       ///< live tets with a vertex that is not Fixed
  double scale = 0;                       ///< largest absolute coordinate of a live vertex
  struct System {
    std::vector<index_t> unknowns;        ///< vertex ids
    std::vector<index_t> knowns;          ///< vertex ids in the right-hand side
    Eigen::SparseMatrix<double> rhs;      ///< unknowns x knowns weights
    /// Curves and surfaces: factorised (SparseLU), each target then costs
    /// two triangular solves. The inside: solved iteratively at each target
    /// (BiCGSTAB, diagonal preconditioner, warm-started by a RepositionHistory):
    /// its factors fill in like a 3D mesh's and would cost more time and
    /// memory than many solves.
    std::shared_ptr<Eigen::SparseLU<Eigen::SparseMatrix<double>>> lu;
    std::shared_ptr<Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::DiagonalPreconditioner<double>>> iterative;
    Eigen::SparseMatrix<double> matrix;   ///< kept for the iterative solver (and its fallback)
  };
  System curves, surfaces, inner;
  std::vector<std::uint8_t> deformable;  ///< per tet slot
  double seconds_surface = 0, seconds_inner = 0;
};

/// 2.5.4.3: classifies the vertices and builds and factorises the systems
/// for the curve, surface and inner vertices of `deformable` (empty: all).
/// `inner` false: the boundary only (the valid-range search).
Status parameterize_vertices(const TetMesh& mesh, const DeformPlan& plan, const std::vector<std::uint8_t>& deformable,
                             VertexParameterization& out, bool inner = true);

/// Earlier solutions of one system of Eq. 2.10. The solution is linear in
/// the knowns' displacements, so a right side in the span of earlier ones
/// is answered by superposition instead of a solve: when only the target
/// value changes, a linear dimension (a distance, a position) costs one
/// solve, every later target none; one whose boundary moves bend a little
/// with the target (a radius: the curves are projected onto the new
/// surfaces) a few solves, one per direction the moves add.
class SolveHistory {
 public:
  /// `solution` (unknowns x 3): the superposition of the stored solutions
  /// for `known` (knowns x 3). True when it is exact to `exact`: what is
  /// left of `known` outside the stored span is below `exact` of its
  /// largest entry, which bounds the solution's error in the max norm (its
  /// rows are weighted means of the knowns). Otherwise `solution` is the
  /// superposed part (a warm start).
  bool superpose(const Eigen::MatrixXd& known, Eigen::Index unknowns, Eigen::MatrixXd& solution,
                 double exact = kExact) const;
  /// Stores a solved pair when `known` adds a direction to the span.
  void add(const Eigen::MatrixXd& known, const Eigen::MatrixXd& solution);
  void clear();
  std::size_t size() const { return basis_.size(); }

  static constexpr double kExact = 1e-12;
  /// For the inner vertices: an error below 1e-9 of the largest boundary
  /// move is far below any use of an inner vertex's position (Improve
  /// moves them next), and spares a solve per target of a radius.
  static constexpr double kInnerExact = 1e-9;
  static constexpr double kNewDirection = 1e-11;
  static constexpr std::size_t kMaxSize = 8;

 private:
  std::vector<Eigen::MatrixXd> basis_, solutions_;
};

/// The solve histories of one parameterisation's three systems.
struct RepositionHistory {
  SolveHistory curves, surfaces, inner;
  void clear() {
    curves.clear();
    surfaces.clear();
    inner.clear();
  }
};

/// 2.5.4.5: the new position of every vertex for the surfaces of `update`:
/// mapped vertices by the map (then onto their deformed neighbours'
/// surfaces), curve, surface and inner vertices by their coordinates, then
/// onto their surfaces. `points` receives all vertex slots.
/// `history` (optional, of this parameterisation): earlier solutions,
/// superposed where they span the new right sides and extended by the
/// solves that are still needed.
void reposition_vertices(const TetMesh& mesh, const DeformRegions& regions, const VertexParameterization& param,
                         const SurfaceUpdate& update, std::vector<Vec3>& points, RepositionHistory* history = nullptr);

/// Whether `points` keep every boundary triangle of the moved and deformed
/// regions unfolded on its surface (the valid-range test, 2.5.3), and why not.
bool boundary_unfolded(const TetMesh& mesh, const DeformRegions& regions, const DeformPlan& plan,
                       const SurfaceUpdate& update, const std::vector<Vec3>& points, std::string* why = nullptr);

/// The valid range of the dimension (2.5.3's by-product): the largest and
/// smallest value that makes valid surfaces and folds no boundary triangle,
/// found on the parameterisation of the whole boundary. Sets plan.valid_min
/// and plan.valid_max (capped at 10 part sizes from the current value).
void find_valid_range(const TetMesh& mesh, const DeformRegions& regions, DeformPlan& plan);

/// For a target beyond the one-step range of find_valid_range: marches the
/// boundary toward it in steps, parameterised again after each (smaller
/// where one would fold), and extends plan's range as far as it gets.
/// True when the target is reached.
bool extend_valid_range(const TetMesh& mesh, const DeformRegions& regions, DeformPlan& plan, double target);

struct DeformMeshOptions {
  double target = std::numeric_limits<double>::quiet_NaN();
  /// Run Improve (2.6) on the deformable region after each step.
  bool improve = true;
  /// Largest fraction of the change in one step; steps are halved further
  /// while one would invert tetrahedra (thesis Fig. 2.55), up to max_steps.
  double max_step_fraction = 1.0;
  int max_steps = 32;
  double quality_floor = 0.3;
  std::function<bool(double, const char*)> progress;
};

struct DeformReport {
  double current = 0, target = 0, valid_min = 0, valid_max = 0;
  int steps = 0;
  std::size_t moved_vertices = 0, deformable_tets = 0, inner_unknowns = 0, surface_unknowns = 0;
  std::size_t inverted_before_improve = 0;
  double min_stretch_before = 0, min_stretch_after = 0;
  /// Seconds per stage; the valid range runs beside the first step's
  /// parameterisation and repositioning, so the stages may add up to more
  /// than the total.
  double seconds_classify = 0, seconds_range = 0, seconds_parameterize = 0, seconds_reposition = 0,
         seconds_improve = 0, seconds_total = 0;
  std::vector<SurfacePrimitive> surfaces;  ///< the regions' surfaces after
  std::vector<std::uint8_t> deformable;    ///< per input tet (tet slot of the mesh given)
  std::vector<std::string> warnings;
  bool aborted = false;
};

struct ReferenceMesh;

/// The whole of 2.5 on `mesh` (built with the regions of `regions` on its
/// faces): classification, valid range, then steps of deformable region,
/// parameterisation, repositioning and (options.improve) Phased ODT on the
/// deformable region with the undeformed mesh as reference. With a NaN
/// target it only measures (report.current, valid range, roles). Fails with
/// a message for a target outside the valid range, a classification that
/// does not fit the type, or tets left inverted. `regions` receives the
/// updated surfaces.
/// `curves` (may be null): the boundary curves with their vertices (mesh
/// ids); the fits of those of moved and deformed regions are refitted after
/// each step, so that Improve keeps their vertices on them.
Status deform_mesh(TetMesh& mesh, DeformRegions& regions, std::vector<BoundaryCurve>* curves,
                   const DeformOptions& options, const DeformMeshOptions& mesh_options, DeformPlan& plan,
                   DeformReport& report);

/// Parameterise once, reposition many (2.5.4): the classification, valid
/// range, deformable region, coordinates and factorisation of one mesh and
/// one control region, kept so that a new target value costs only the
/// repositioning (dragging Target Value in ParaView, a sweep over values),
/// as long as the region built for the largest change asked so far reaches.
/// Without improvement: a change that would invert tetrahedra is refused.
class DeformSession {
 public:
  /// Classification and valid range on a copy of `mesh`.
  Status prepare(const TetMesh& mesh, const DeformRegions& regions, const DeformOptions& options);
  /// The vertex positions and surfaces for `target` (the mesh's vertex
  /// slots). `reused` tells whether the parameterisation was kept.
  Status reposition(double target, std::vector<Vec3>& points, std::vector<SurfacePrimitive>& surfaces,
                    bool* reused = nullptr);
  const DeformPlan& plan() const { return plan_; }
  const TetMesh& mesh() const { return mesh_; }
  const VertexParameterization& parameterization() const { return param_; }

 private:
  TetMesh mesh_;
  DeformRegions regions_;
  DeformPlan plan_;
  VertexParameterization param_;
  RepositionHistory history_;  ///< of param_
  double reach_ = -1;  ///< the reach param_ was built for (< 0: none)
  double edge_ = 0;
};

/// The fits of the curves that bound a moved or deformed region, refitted
/// on their live vertices (a curve left with too few becomes unclassified,
/// so its vertices follow the two surfaces).
void refit_boundary_curves(const TetMesh& mesh, const std::vector<SurfacePrimitive>& surfaces, const DeformPlan& plan,
                           std::vector<BoundaryCurve>& curves);

}  // namespace femorph
