// Contact between objects in FEMorph Adapt (thesis 3.4.2, 3.5.2, 3.5.4,
// 3.5.5): the objects' analytic surface regions, the regions of two objects
// that overlap at a pose, and the vertices on the overlap.
#pragma once

#include "adapt/adapt.h"
#include "geometry/surface_chart.h"

#include <map>

namespace femorph {

using Tri = std::array<index_t, 3>;

/// The boundary of one object: its faces (outward, mesh vertex ids), where
/// its tets meet a tet of another material or the domain boundary.
struct ObjectBoundary {
  int material = 0;
  std::vector<Tri> faces;
};

/// Every object's (material > 0) boundary, by ascending material.
/// `material_by_origin` is indexed by tet_origin.
std::vector<ObjectBoundary> object_boundaries(const TetMesh& mesh, const std::vector<int>& material_by_origin);

/// An object's analytic surface regions (the surface information of thesis
/// 2.5.1.1 that 3.4.2 uses), fitted once by the segmentation (2.4) in the
/// frame of the points given; unknown regions never take part in contact.
struct ObjectSurfaceInfo {
  int material = 0;
  std::vector<SurfacePrimitive> regions;
  double mean_edge = 0;
  double scale = 0;  ///< the object's bounding-box diagonal
};

/// Segments the boundary of one object (thesis 2.4 at its defaults).
Status segment_object(const std::vector<Vec3>& points, const ObjectBoundary& boundary, ObjectSurfaceInfo& out);

/// The region of each face: the analytic region whose surface passes
/// within `tolerance` of the face's three vertices, with the face's normal
/// within 30 degrees of the surface normal at its centroid (the nearest when
/// several fit; the centroid of a chord face is off a curved surface);
/// -1 when none does. `point(v)` gives vertex v's position in
/// the frame of `regions`.
std::vector<index_t> classify_object_faces(const std::function<Vec3(index_t)>& point, const std::vector<Tri>& faces,
                                           const std::vector<SurfacePrimitive>& regions, double tolerance);

/// One contact (thesis 3.4.2): a region of the moving object on the same
/// surface as a region of another object, facing it, and overlapping it.
struct ContactRegion {
  int moving_material = 0, other_material = 0;
  index_t moving_region = kInvalidIndex, other_region = kInvalidIndex;
  SurfacePrimitive surface;                 ///< the other object's (it is not moving)
  /// V_m^O and V_c^O: vertices of each region inside the other region's
  /// extent (in the surface's chart), within the tolerance.
  std::vector<index_t> moving_vertices, other_vertices;
  /// Faces of each region whose centroid lies inside the other region.
  std::vector<index_t> moving_faces, other_faces;
  double moving_area = 0;                   ///< area of moving_faces
};

/// Thesis 3.4.2 steps 2-3 between the moving object and one other object:
/// pairs of regions on the same surface (position, radius and axis within
/// `tolerance`, axes within tolerance / scale radians) with opposite
/// outward normals, and the vertices and faces of each inside the other,
/// tested in the 2D chart of the surface. `moving_point(v)` gives the
/// moving object's vertex v at the pose tested; its regions are given at
/// that pose. Faces are indexed as in the ObjectBoundary lists. With
/// `reach` > 0, vertices within `reach` of the other region in the chart
/// join the vertex sets, and a pair whose sets are not empty is reported
/// even without faces in contact: objects about to touch (3.5.2's removal
/// ahead of the contact).
std::vector<ContactRegion> detect_contacts(const std::function<Vec3(index_t)>& moving_point,
                                           const ObjectBoundary& moving, const std::vector<index_t>& moving_face_region,
                                           const std::vector<SurfacePrimitive>& moving_regions,
                                           const std::vector<Vec3>& points, const ObjectBoundary& other,
                                           const std::vector<index_t>& other_face_region,
                                           const std::vector<SurfacePrimitive>& other_regions, double tolerance,
                                           double scale, double reach = 0);

/// The contact surfaces of the moving object and of the other object inside
/// the removed zone, merged into one surface (thesis 3.5.4, done by
/// re-triangulation in the surface's chart instead of vertex pairing).
struct MergedContact {
  std::vector<Vec3> new_points;  ///< crossings of the two boundary lines (3.5.4.2), ids first_new_id + k
  std::vector<HoleFacet> faces;  ///< the merged surface, materials on both sides
  /// Boundary edges of the two patches that received points, keyed by
  /// (min id, max id): the points in order from the min id to the max id.
  std::map<std::pair<index_t, index_t>, std::vector<index_t>> split_edges;
  double contact_area = 0;       ///< area of the faces between the two objects
  /// Vertices replaced everywhere: moving-patch vertices at the position of
  /// an other-patch vertex (to 1e-9 of the spacing) by it, other-patch
  /// boundary vertices slid onto a moving one by that one.
  std::map<index_t, index_t> replaced;
};

/// Merges the moving object's faces (at the new pose) and the other's on
/// one surface: the union of both patches re-triangulated (constrained
/// Delaunay) in the surface's chart, with each patch's boundary edges kept
/// (split where the two boundary lines cross, at a point of the other
/// patch's edge, and at the other patch's boundary vertices on them), the moving patch's vertices dropped inside
/// the other patch and the other's inner vertices dropped near the moving
/// patch's boundary (closer than `spacing`). Each face gets its sides:
/// contact faces moving | other, the rest object | `space_material`. The two
/// patches must not share vertex ids (the caller gives the moving object's
/// shared vertices new ids). An other-patch boundary point closer than 0.3
/// spacing to a moving boundary point on its line is replaced by it (it
/// slides along its line) when `movable` says it may (not on the zone's
/// boundary). Fails, saying why, on patches that wrap around their surface
/// or boundary lines that cannot be kept.
Status merge_contact_surfaces(const SurfacePrimitive& surface, const std::vector<Tri>& moving_faces,
                              const std::vector<Tri>& other_faces, const std::function<Vec3(index_t)>& point,
                              int moving_material, int other_material, int space_material, index_t first_new_id,
                              double spacing, MergedContact& out,
                              const std::function<bool(index_t)>& movable = {});

struct DensityGrid;
/// 3.6 on a region that holds objects' tets (a contact zone): the tets of
/// one material are improved as a region of their own
/// (improve_deformed_region, their interfaces with the others fixed; tets
/// around pinched vertices left out) and put back into the region.
Status improve_material_part(RegionMesh& rm, int material, const std::vector<int>& material_by_origin,
                             const TetMesh& mesh, const DensityGrid* density, double density_scale,
                             double quality_floor);
/// improve_material_part for every material of the region.
Status improve_material_parts(RegionMesh& rm, const std::vector<int>& material_by_origin, const TetMesh& mesh,
                              const DensityGrid* density, double density_scale, double quality_floor);

/// What an AdaptSession keeps for contact (adapt_contact.cpp).
struct AdaptContactState {
  ObjectSurfaceInfo moving;                 ///< rest frame
  std::vector<ObjectSurfaceInfo> others;    ///< fixed objects
  std::vector<Vec3> other_lo, other_hi;     ///< their boxes
  Vec3 moving_lo = Vec3::Zero(), moving_hi = Vec3::Zero();  ///< rest frame
  double tolerance = 0;                     ///< on surfaces, lengths
  double spacing = 0;                       ///< the objects' mean surface edge
  std::vector<index_t> shared;              ///< vertices of the moving object and another
  /// The last contacts_at() answer, for the same pose and mesh (a step
  /// asks twice: the penetration check and the step itself).
  RigidPose cached_pose;
  std::size_t cached_version = static_cast<std::size_t>(-1);
  std::vector<ContactRegion> cached;
};

/// A primitive moved by a rigid pose.
SurfacePrimitive transform_surface(const SurfacePrimitive& s, const RigidPose& pose);

}  // namespace femorph
