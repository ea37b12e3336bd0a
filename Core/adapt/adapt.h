// FEMorph Adapt, thesis chapter 3: a rigid object moves through a conformal
// space mesh step by step, and only the space elements near it are adapted.
//
// One step (Fig. 3.1, A2; Fig. 3.6) without contact:
//   build_vertex_grid        G_v, the fixed vertex search grid (3.4.1)
//   build_distance_grid      G_d, the distance field moving with the object (3.4.1)
//   extract_deformed_region  K_Df from G_d and G_v (3.4.3)
//   embed_deformed_region    rigid transformation, MVC embedding of K_Df's
//                            inner vertices (3.5.3, Eqs. 3.1-3.2)
//   improve_deformed_region  Improve's Phased ODT on K_Df (3.6)
// chained by adapt_step; AdaptSession keeps the state between steps.
// With contact (contact.h, adapt_contact.cpp), the step also:
//   detect_contacts          pairs of object regions on one surface (3.4.2)
//   contact_zone             the tets removed around the contact (3.5.2)
//   merge_contact_surfaces   one surface for the two patches (3.5.4)
//   tetrahedralize_hole      TetGen's refill of the zone (3.5.5)
//   improve_material_part    3.6 on each material of the region
#pragma once

#include "common/types.h"
#include "mesh/tet_mesh.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace femorph {

/// A rigid pose x -> R x + t.
struct RigidPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Vec3 t = Vec3::Zero();

  Vec3 apply(const Vec3& x) const { return R * x + t; }
  RigidPose inverse() const;
  /// (this o other)(x) = this(other(x)).
  RigidPose after(const RigidPose& other) const;
  /// The fraction s in [0, 1] of this motion from the identity: rotation
  /// angle and translation scaled along the screw (sub-steps of a step).
  RigidPose fraction(double s) const;
};

/// The motion of the moving object: the pose of step n, from step 0 (the
/// input, identity).
struct RigidMotion {
  /// x_n = c + n t + R(axis, n angle) (x_0 - c).
  Vec3 translation_per_step = Vec3::Zero();
  Vec3 rotation_axis = Vec3::UnitX();
  Vec3 rotation_center = Vec3::Zero();
  double rotation_degrees_per_step = 0;
  /// When not empty: the absolute pose of step n is table[n - 1] (the
  /// filter's motion table); steps beyond the table are invalid.
  std::vector<RigidPose> table;

  RigidPose pose(int step) const;
};

/// A 4x4 row-major matrix (m00..m33) as a rigid pose. Fails, saying why,
/// when it is not finite, its last row is not (0 0 0 1), or its 3x3 block is
/// not a rotation within `tolerance` (R^T R = I, det R = 1).
Status rigid_pose_from_matrix(const double m[16], RigidPose& pose, double tolerance = 1e-6);

struct AdaptOptions {
  /// Material id of the moving object (> 0; 0 is space).
  int moving_object = 1;
  /// Cell edge of G_d and G_v; <= 0: 6 x the largest displacement of an
  /// object vertex in one step (3.4.1).
  double grid_cell_size = 0;
  /// delta_dist of 3.4.3 in cells of G_d: G_v cells nearer than this to the
  /// object hold the deformed region's vertices (thesis: 3).
  double distance_threshold = 3;
  /// Quality improvement (3.6) on the deformed region every step.
  bool improve = true;
  /// Improve's quality floor (PhasedOdtOptions::quality_floor); <= 0: 1.1 x
  /// the input's minimum stretch, within [0.1, 0.4] (the steps then stay
  /// above the input's minimum).
  double quality_floor = 0;
  /// A step whose embedding inverts elements is split into halves, at most
  /// this many times (2^k sub-steps).
  int max_halvings = 5;
};

/// What one step did (a row of the filter's table).
struct AdaptStepReport {
  int step = 0;
  std::size_t vertices = 0, tets = 0;
  double min_stretch = 0, mean_stretch = 0;
  std::size_t deformed_region_tets = 0;  ///< K_Df, summed over sub-steps
  std::size_t inner_vertices = 0;       ///< unknowns of Eq. 3.2, summed over sub-steps
  /// Vertices whose position changed in the step (the object's, the moved
  /// and the new space vertices; over sub-steps, an upper bound).
  std::size_t moved_vertices = 0;
  /// Faces shared by tets of two different objects (material > 0 each)
  /// after the step (3.7.3's contact triangles); 0 with a single object.
  std::size_t contact_faces = 0;
  int substeps = 1;
  double seconds = 0;
  /// The time by part: G_v and K_Df (3.4), the region as a mesh of its own,
  /// the embedding (3.5.3), the improvement (3.6), the splice back.
  double seconds_region = 0, seconds_submesh = 0, seconds_embed = 0, seconds_improve = 0, seconds_splice = 0;
  double seconds_contact = 0;  ///< contact zone: patches merged, refilled
  std::vector<std::string> warnings;
};

/// The mesh of the current step for output. Ids are dense.
struct AdaptOutput {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<int> material;                  ///< per tet
  std::vector<index_t> cell_origin;           ///< per tet: the input cell it descends from
  std::vector<VertexStencil> point_origin;    ///< per point: the input points it descends from (material-following)
  /// Per point: its data in the previous step's output (dense ids, weights):
  /// the same point for the object's vertices and the unchanged ones, the
  /// previous field interpolated at its position for the moved space
  /// vertices (field transfer). Empty at step 0.
  std::vector<VertexStencil> point_previous;
};

/// 3.4.1: G_v, the fixed grid of the vertices: cell (i, j, k) holds the
/// live vertices inside it (CSR).
struct VertexGrid {
  Vec3 origin = Vec3::Zero();
  double h = 1;
  std::array<int, 3> n{{0, 0, 0}};
  std::vector<index_t> start;  ///< n0 n1 n2 + 1 offsets into `vertices`
  std::vector<index_t> vertices;
  std::size_t cell_id(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * n[1] + j) * n[0] + i;
  }
};
/// Cells of edge h over the box [lo, hi] (slightly padded).
VertexGrid build_vertex_grid(const TetMesh& mesh, const Vec3& lo, const Vec3& hi, double h);

/// 3.4.1: G_d, the distance field of the moving object, in the object's
/// frame at step 0: cell distances (in cells) from the cells holding the
/// object's surface vertices, by the simplified fast marching of Fig. 3.2
/// (26-neighbour steps of 1), up to `threshold` + 1; the grid covers the
/// object's box padded by that much.
struct DistanceGrid {
  Vec3 origin = Vec3::Zero();
  double h = 1;
  std::array<int, 3> n{{0, 0, 0}};
  std::vector<float> distance;  ///< per cell; +inf beyond the threshold
  /// Distance at a point of the object's frame; +inf outside the grid.
  double at(const Vec3& x) const;
};
DistanceGrid build_distance_grid(const std::vector<Vec3>& surface_points, double h, double threshold);

/// 3.4.3: K_Df, the space tets (material 0) with a vertex in a G_v cell whose
/// centre, mapped into the object's frame by `to_object`, lies nearer than
/// `threshold` cells to the object; closed so that it is a manifold
/// submesh (a boundary vertex whose region or outside part of the ball is
/// not face-connected takes its whole space ball in). Returns tet slots.
std::vector<index_t> extract_deformed_region(const TetMesh& mesh, const std::vector<int>& tet_material,
                                             const VertexGrid& vertex_grid, const DistanceGrid& distance_grid,
                                             const RigidPose& to_object, double threshold);

/// A copy of tets of a TetMesh as a mesh of its own (the deformed region),
/// with the map back to the big mesh.
/// Beyond the thesis: grows `region` (tets of `mesh`) into a manifold
/// submesh: a vertex whose ball is pinched (the region's part or the rest
/// not face-connected around it) takes its whole ball, the tets `may_take`
/// accepts; the tets added bring their vertices to check.
void close_region(const TetMesh& mesh, std::vector<index_t>& region, const std::function<bool(index_t)>& may_take);

/// The opposite: shrinks `region` into a manifold submesh by dropping the
/// region's tets around each pinched vertex (where objects touch along a
/// line, the space between them is pinched).
void open_region(const TetMesh& mesh, std::vector<index_t>& region);

struct RegionMesh {
  TetMesh mesh;
  std::vector<index_t> global_vertex;  ///< local vertex -> big mesh vertex (build-time slots)
  std::vector<index_t> global_tet;     ///< local tet -> big mesh tet (build-time slots)
};

/// The tets `region` of `mesh` as a RegionMesh (its vertices in the order
/// first met). Fails when they do not form a valid manifold mesh.
Status make_region_mesh(const TetMesh& mesh, const std::vector<index_t>& region, RegionMesh& out);

/// 3.5.3 (Eqs. 3.1-3.2) on the region: its vertices in `moved` (by local
/// id, 1 = moved) go to `moved_position`, its other boundary vertices stay,
/// and its inner vertices are solved from their 3D mean value coordinates in
/// their 1-rings (computed before the move). Returns the inner vertex count,
/// or fails when the system cannot be solved.
Status embed_deformed_region(RegionMesh& region, const std::vector<std::uint8_t>& moved,
                             const std::vector<Vec3>& moved_position, std::size_t* inner_vertices);

/// Field transfer (beyond the thesis): where each vertex of the adapted
/// region `now` takes its data from in the region as it was (`before`: the
/// region mesh before the embedding, same build-time vertex ids), as a
/// stencil over `origin` (per build-time vertex of `before`, stencils into
/// the previous step's points): linear interpolation at the vertex's
/// position. A vertex whose position lies outside the old region (in the
/// volume the object left) is handed to `beyond` with the position and the
/// three vertices of the boundary face the walk left by; when it finds
/// nothing, the vertex keeps its own (or its build-time stencil's) data.
/// Returns one stencil per vertex slot of `now`.
using TransferBeyond = std::function<bool(const Vec3& p, const std::array<index_t, 3>& face, VertexStencil& out)>;
std::vector<VertexStencil> transfer_point_data(const TetMesh& before, const TetMesh& now,
                                               const std::vector<VertexStencil>& origin,
                                               const TransferBeyond& beyond = nullptr);

/// 3.6: Improve's Phased ODT on the region with its boundary fixed; the
/// target density is the input's (a spatial field). Repairs inverted tets.
/// `density_scale` multiplies the target density (AdaptSession keeps the
/// vertex count with it).
struct DensityGrid;
Status improve_deformed_region(RegionMesh& region, const DensityGrid* density, double density_scale,
                               double quality_floor);

/// Penetration (bad motion input): walks from each of `vertices` (the moving
/// object's surface vertices) to its position in `target` through the tets
/// (a visibility walk, exact orientation tests). Fails, naming the vertex's
/// target position, when the walk leaves the domain through its outer
/// boundary or ends in a tet of another object (material > 0 and not
/// `moving`). `material_by_origin` is indexed by tet_origin.
Status detect_penetration(const TetMesh& mesh, const std::vector<int>& material_by_origin, int moving,
                          const std::vector<index_t>& vertices, const std::vector<Vec3>& target);

/// Penetration in the assembly mode (3.7.4, no space mesh; beyond the
/// thesis): fails, naming the point, when one of `points` (an object's
/// surface points at a pose) lies inside a tet of an object other than
/// `material` (material > 0) farther than `tolerance` from that object's
/// boundary faces. Touching surfaces, and a curved surface's chords of two
/// meshes, stay within the tolerance. `material_by_origin` is indexed by
/// tet_origin.
Status detect_overlap(const TetMesh& mesh, const std::vector<int>& material_by_origin, int material,
                      const std::vector<Vec3>& points, double tolerance);
/// detect_overlap's tolerance in the assembly mode, in the parts' mean
/// surface edge: above the chord sag of a curved surface meshed by two parts
/// (edge^2 / 8r, below 0.1 edge for r > 1.25 edge).
constexpr double kOverlapTolerance = 0.1;
/// The points of the boundary faces of the tets of one material (faces
/// towards another material or the outside).
std::vector<Vec3> part_surface_points(const TetMesh& mesh, const std::vector<int>& material_by_origin, int material);

/// Beyond the thesis: a space mesh (material 0) around the objects of a tet
/// mesh (every tet an object's, material > 0), filling the box [lo, hi] by
/// TetGen's constrained Delaunay refinement with no Steiner point on the
/// objects' surfaces nor on the box (whose faces are cut into triangles of
/// edge `edge`; <= 0: 4 x the objects' mean surface edge); the sizes grade
/// between the two. The objects' tets and points come first in the output,
/// as given.
Status mesh_space_around(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                         const std::vector<int>& material, const Vec3& lo, const Vec3& hi, double edge,
                         std::vector<Vec3>& out_points, std::vector<Tet>& out_tets, std::vector<int>& out_material);

/// The faces shared by live tets of two different objects (material > 0
/// each; `material_by_origin` indexed by tet_origin): thesis 3.7.3's contact
/// triangles, each counted once.
std::size_t count_object_contact_faces(const TetMesh& mesh, const std::vector<int>& material_by_origin);

/// Mean and minimum stretch of the live tets of a mesh.
void stretch_range(const TetMesh& mesh, double* min, double* mean);

struct ContactRegion;
struct AdaptContactState;

class AdaptSession {
 public:
  /// Builds the session from the input mesh (tets positively oriented or all
  /// negative), a material id per tet and the motion. Fails with a message
  /// naming the problem (no tet of the moving object, an invalid mesh, an
  /// interface between the object and space that is not conformal).
  /// A mesh with no space tet (material 0) is an assembly (thesis 3.7.4):
  /// parts meshed separately, their touching surfaces on the domain's
  /// boundary, not conformal; each step moves the moving part and makes its
  /// contacts conformal (adapt_contact.cpp); parts that overlap are refused
  /// (detect_overlap).
  Status init(const std::vector<Vec3>& points, const std::vector<Tet>& tets, const std::vector<int>& material,
              const RigidMotion& motion, const AdaptOptions& options);
  /// Computes step current_step() + 1. On failure the session stays at the
  /// step it was (a refused step: penetration, a collapse of the space
  /// between the object and the boundary), and the message says why.
  Status advance(AdaptStepReport* report = nullptr);
  int current_step() const { return step_; }
  /// True for an assembly (no space mesh, thesis 3.7.4).
  bool assembly() const { return assembly_; }
  /// The report of step 0 (the input), whatever step the session is at.
  AdaptStepReport initial_report() const;
  AdaptOutput output() const;
  std::size_t memory_bytes() const;

 private:
  /// One sub-step to pose `to` (adapt_step.cpp); true in *retry when a
  /// smaller sub-step may succeed. With `keep_quality`, a region whose
  /// minimum stretch ends below the input's minimum is such a failure.
  Status move_to(const RigidPose& to, AdaptStepReport& report, bool* retry, bool keep_quality);
  void refresh_stretch(const std::vector<index_t>& removed, const std::vector<index_t>& added);
  // Contact (adapt_contact.cpp): the objects' segmented surfaces, contacts
  // at a pose, the zone removed around them, its refill in the region, the
  // moving object's vertex lists after a refill changed them.
  Status init_contact();
  std::vector<ContactRegion> contacts_at(const RigidPose& to) const;  ///< cached find_contacts
  std::vector<ContactRegion> find_contacts(const RigidPose& to) const;
  std::size_t mesh_version_ = 0;  ///< counts the changes of mesh_ (contacts_at's cache)
  std::vector<index_t> contact_zone(const std::vector<ContactRegion>& contacts) const;
  /// The tets of the fixed objects (material > 0, not the moving one; with
  /// `moving`, the moving one's too) that share a vertex with the zone and
  /// are not in it (one ring).
  std::vector<index_t> fixed_object_ring(const std::vector<index_t>& zone, bool moving = false) const;
  Status remesh_contact_zone(RegionMesh& rm, const std::vector<index_t>& zone,
                             const std::vector<ContactRegion>& contacts, const RigidPose& to);
  void rebuild_object_vertices(const std::vector<index_t>& placed, const RigidPose& to);
  /// Penetration through a contact: a vertex the moving object shares with
  /// another one, moved to `target`, must not go into that object beyond
  /// the contact surface (the walk of detect_penetration cannot tell).
  Status check_shared_vertices(const RigidPose& target) const;
  /// detect_overlap of the moving part's surface at `target` (assembly).
  Status check_assembly_overlap(const RigidPose& target) const;
  std::shared_ptr<AdaptContactState> contact_;
  bool assembly_ = false;                  ///< no space mesh (3.7.4)
  TetMesh mesh_;
  std::vector<int> material_;              ///< per input tet (by tet_origin)
  std::vector<index_t> object_vertices_;   ///< the moving object's vertices
  std::vector<Vec3> object_rest_;          ///< their positions at step 0
  std::vector<index_t> object_index_;      ///< per vertex slot: index into object_vertices_, or -1
  std::vector<index_t> object_surface_;    ///< the moving object's surface vertices
  RigidMotion motion_;
  AdaptOptions options_;
  RigidPose pose_;                          ///< pose of the current step
  DistanceGrid distance_grid_;
  std::shared_ptr<const DensityGrid> density_;
  Vec3 box_lo_ = Vec3::Zero(), box_hi_ = Vec3::Zero();
  double cell_ = 1;
  double quality_floor_ = 0.3;
  double input_min_stretch_ = 0;
  AdaptStepReport initial_;                 ///< step 0, the input
  /// Scale of the target density: the improvement of 3.6 drives a region
  /// toward isotropic tets of the input's mean edge length, which for a
  /// mesh of mixed edge lengths (the 12-tet cubes of 3.7.2) has fewer
  /// vertices than the input; each step corrects the scale by the region's
  /// vertex change (beyond the thesis: the vertex count stays near the
  /// input's over hundreds of steps).
  double density_scale_ = 1;
  std::size_t input_vertices_ = 0;
  int step_ = 0;
  std::vector<double> stretch_;             ///< per tet slot (cache; NaN dead)
  std::vector<VertexStencil> step_origin_;  ///< per vertex slot: AdaptOutput::point_previous
};

// ---- Thesis 3.5.5, the contact case: refilling a hole -----------------------

/// One triangle of a hole's PLC: vertices (indices into the points), and the
/// material on each side: `front` on the side its normal (right hand v0, v1,
/// v2) points to, `back` on the other; -1 = outside the hole (the kept mesh,
/// or outside the domain).
struct HoleFacet {
  std::array<index_t, 3> v;
  int front;
  int back;
};

/// 3.5.5: fills the hole bounded by the facets with -1 on one side (a closed,
/// edge-manifold surface) and cut by the facets with materials on both sides
/// (interfaces), by TetGen's constrained Delaunay refinement (-pYq<ratio>):
/// no Steiner point on any facet, every facet a face of the refill.
/// `radius_edge_ratio` is -q's bound (>= 1; mesh_space_around uses 1.4).
/// Only the facets' points go to TetGen; the new points the refill uses are
/// appended to `points`; `tets` (positively oriented) and `material` are
/// overwritten with the refill, each tet taking the material of the facet
/// sides around its region (flood fill; regions facing -1, e.g. kept tets
/// enclosed by the hole, are dropped). Fails, saying why and leaving
/// `points` as it was, on an open or non-manifold hole boundary, a
/// degenerate or repeated facet, facet sides that give a region two
/// materials, a TetGen error, or a split facet.
Status tetrahedralize_hole(std::vector<Vec3>& points, const std::vector<HoleFacet>& facets,
                           double radius_edge_ratio, std::vector<Tet>& tets, std::vector<int>& material);

/// The facets of the hole left by removing the live tets `removed` from
/// `mesh` (ids: vertex slots): the faces between a removed tet and a kept
/// one or the outside (the removed tet's material inside, -1 outside), and
/// the faces between removed tets of different materials (interfaces).
/// `tet_material` gives the material of a tet slot.
std::vector<HoleFacet> hole_facets(const TetMesh& mesh, const std::vector<index_t>& removed,
                                   const std::function<int(index_t)>& tet_material);

}  // namespace femorph
