// Contact between objects in FEMorph Adapt (thesis 3.4.2, 3.5.2, 3.5.4,
// 3.5.5): the objects' analytic surface regions, the regions of two objects
// that overlap at a pose, and the vertices on the overlap.
#pragma once

#include "adapt/adapt.h"
#include "geometry/surface_chart.h"

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
/// within `tolerance` of the face's three vertices and centroid, with the
/// face's normal within 30 degrees of the surface normal (the nearest when
/// several fit); -1 when none does. `point(v)` gives vertex v's position in
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
/// that pose. Faces are indexed as in the ObjectBoundary lists.
std::vector<ContactRegion> detect_contacts(const std::function<Vec3(index_t)>& moving_point,
                                           const ObjectBoundary& moving, const std::vector<index_t>& moving_face_region,
                                           const std::vector<SurfacePrimitive>& moving_regions,
                                           const std::vector<Vec3>& points, const ObjectBoundary& other,
                                           const std::vector<index_t>& other_face_region,
                                           const std::vector<SurfacePrimitive>& other_regions, double tolerance,
                                           double scale);

/// A primitive moved by a rigid pose.
SurfacePrimitive transform_surface(const SurfacePrimitive& s, const RigidPose& pose);

}  // namespace femorph
