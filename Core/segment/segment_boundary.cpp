// The boundary of a tetrahedral mesh segmented (thesis 2.4): the one sequence
// FEMorph Segment runs and FEMorph Improve runs on a mesh without a
// segmentation.
#include "mesh/count_coincident_points.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"

#include <string>

namespace femorph {

Status segment_boundary(const TetMesh& mesh, const SegmentationParams& params, SurfaceMesh& surface,
                        Segmentation& out, const SegmentationProgress& progress) {
  out = Segmentation();
  SurfaceReport report;
  if (progress && !progress(0.0, "extracting the boundary surface")) return Status::failure("aborted");
  const Status extracted = extract_boundary_surface(mesh, surface, &report);
  if (!extracted) {
    return Status::failure("the boundary surface cannot be segmented: " + extracted.message +
                           " (open edges: " + std::to_string(report.open_edges) +
                           ", non-manifold edges: " + std::to_string(report.nonmanifold_edges) +
                           ", inconsistently oriented edges: " + std::to_string(report.misoriented_edges) + ").");
  }
  const Status segmented = segment_surface(surface, params, out, progress);
  if (!segmented) {
    out.warnings.clear();
    return Status::failure("the segmentation failed: " + segmented.message);
  }
  // Beyond the thesis: an unmerged seam (duplicate nodes between
  // two parts of one body) is a closed boundary inside the part; the
  // segmentation then splits every face it crosses into many regions,
  // silently. Boundary points within a millionth of the mean edge of
  // another boundary point are such duplicates: no real surface mesh has
  // them.
  const std::size_t coincident =
      count_coincident_points(surface.points, kCoincidentPointTolerance * surface.mean_edge_length);
  if (coincident > 0)
    out.warnings.insert(out.warnings.begin(),
                        std::to_string(coincident) + " boundary points lie on top of other boundary points (within " +
                            "1e-6 of the mean edge length) but are separate points: the mesh has unmerged seams " +
                            "(duplicate nodes), which the segmentation takes for faces inside the part and splits " +
                            "its regions along. Merge coincident points first (in ParaView: Clean to Grid; in VTK: " +
                            "vtkStaticCleanUnstructuredGrid), then segment again.");
  if (report.degenerate_triangles > 0) {
    const std::size_t n = report.degenerate_triangles;
    out.warnings.insert(out.warnings.begin(),
                        std::to_string(n) + (n == 1 ? " boundary triangle is" : " boundary triangles are") +
                            " degenerate (zero area); " + (n == 1 ? "it has" : "they have") +
                            " no normal and may be left in unknown regions.");
  }
  return segmented;
}

}  // namespace femorph
