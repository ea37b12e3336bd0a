/**
 * @class   vtkFEMorphSegmentationArrays
 * @brief   femorph::Segmentation <-> the VTK arrays of docs/ARCHITECTURE.md, shared by
 *          FEMorph Segment (which writes them) and the filters that read them
 *
 * Static helpers, no state, like vtkFEMorphMeshConversion. The segmentation
 * travels with the mesh as ordinary arrays, so it survives .vtu files,
 * ParaView pipelines and client-server transfer:
 *
 * On the tetrahedral mesh (WriteToMesh(), read back by ReadFromMesh()):
 * - cell data `FaceRegion` (int, 4 components): region id of the face
 *   opposite local vertex i of the cell, -1 for interior faces. The local
 *   numbering is the grid's own connectivity (an input the core flipped to
 *   positive orientation keeps its numbering in the arrays);
 * - point data `VertexClass` (unsigned char): 0 inner, 1 surface, 2 curve,
 *   3 corner (thesis Fig. 2.37);
 * - field data, one tuple per region: `RegionType` (int: 0 plane, 1 cylinder,
 *   2 cone, 3 sphere, 4 torus, 5 unknown), `RegionParameters` (double,
 *   femorph::kRegionParameterWidth components, layout in
 *   Core/segment/segmentation.h: point, axis, radius, minor radius, half
 *   angle in radians, convexity, fit RMS, area), `RegionConvexity` (int:
 *   0 not applicable, 1 convex, 2 concave);
 * - field data, one tuple per boundary curve: `CurveType` (int, the codes of
 *   Core/geometry/curve_primitive.h: 0 line, 1 circle, 2 circular arc,
 *   3 ellipse, 4 elliptic arc, 5 parabola, 6 hyperbola, 7 unclassified),
 *   `CurveParameters` (double, femorph::kCurveParameterWidth components:
 *   center, normal, direction, radius, minor radius, start, end, region a,
 *   region b, continuity), `CurveClosed` (unsigned char, 1 for a loop);
 * - field data `CurveVertices` (vtkIdType): the ordered mesh point ids of
 *   every curve, concatenated (a loop does not repeat its first point), and
 *   `CurveOffsets` (vtkIdType, curves + 1 values): curve c is
 *   CurveVertices[CurveOffsets[c] .. CurveOffsets[c + 1]);
 * - field data `SegmentationTimes` (double, one tuple, a named component per
 *   step of thesis Table 2.9, seconds).
 *
 * The boundary surface (WriteSurface()): a vtkPolyData whose points are the
 * surface vertices (point data `MeshPointId`, vtkIdType: the point of the
 * tetrahedral mesh; `VertexClass`; the mesh's point data copied), whose
 * polys are the triangles and whose lines are the boundary curves as
 * VTK_POLY_LINE cells (a loop repeats its first point at the end). Cell data,
 * shared by both kinds: `RegionId`, `RegionType` (-1 on curves), `CurveId`,
 * `CurveType` (-1 on triangles), all int. vtkPolyData numbers lines before
 * polys: cells 0 .. curves - 1 are the curves.
 *
 * The region table (WriteRegionTable()): one row per region, columns
 * RegionId (int), TypeName (string: plane, cylinder, cone, sphere, torus,
 * unknown), Radius (cylinder, sphere), MajorRadius and MinorRadius (torus),
 * HalfAngle (cone, degrees), Axis (3 components; cylinder, cone, torus),
 * Center (3; a point on a cylinder's axis, the centre of a sphere or torus),
 * Apex (3; cone), Normal (3) and Point (3) for planes, Area, Convexity
 * (string: convex, concave or empty), TriangleCount (int), FitResidual (RMS
 * distance of the region's vertices to the fit), Neighbors (string of region
 * ids, e.g. "2 5 7"). Doubles are NaN where a column does not apply.
 *
 * The writers check the segmentation against the surface first (sizes, ids
 * in range) and return a failed status naming the problem instead of
 * writing inconsistent arrays. Messages are returned, not printed.
 *
 * This header names core types, so it is private to the module (not wrapped).
 *
 * @sa vtkFEMorphSegment, vtkFEMorphMeshConversion
 */
#ifndef vtkFEMorphSegmentationArrays_h
#define vtkFEMorphSegmentationArrays_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphMeshConversion.h" // For the array names
#include "vtkSmartPointer.h"    // For vtkSmartPointer
#include "vtkType.h"            // For vtkIdType

#include "common/types.h"          // femorph::Status
#include "mesh/surface_mesh.h"     // femorph::SurfaceMesh
#include "segment/segmentation.h"  // femorph::Segmentation

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

class vtkPolyData;
class vtkTable;
class vtkUnstructuredGrid;
class vtkFieldData;

class FEMORPHFILTERS_EXPORT vtkFEMorphSegmentationArrays
{
public:
  ///@{
  /// Array names (docs/ARCHITECTURE.md).
  static constexpr const char* FaceRegionName = vtkFEMorphMeshConversion::FaceRegionName;
  static constexpr const char* VertexClassName = vtkFEMorphMeshConversion::VertexClassName;
  static constexpr const char* RegionTypeName = "RegionType";
  static constexpr const char* RegionParametersName = "RegionParameters";
  static constexpr const char* RegionConvexityName = "RegionConvexity";
  static constexpr const char* CurveTypeName = "CurveType";
  static constexpr const char* CurveParametersName = "CurveParameters";
  static constexpr const char* CurveClosedName = "CurveClosed";
  static constexpr const char* CurveVerticesName = "CurveVertices";
  static constexpr const char* CurveOffsetsName = "CurveOffsets";
  static constexpr const char* SegmentationTimesName = "SegmentationTimes";
  static constexpr const char* MeshPointIdName = "MeshPointId";
  static constexpr const char* RegionIdName = "RegionId";
  static constexpr const char* CurveIdName = "CurveId";
  ///@}

  /// The columns of the region table, in order.
  static const std::vector<std::string>& RegionTableColumns();

  /**
   * Checks that `segmentation` fits `surface` (per-triangle and per-vertex
   * sizes, region, curve and vertex ids in range, source_vertex and
   * source_face present) and, when `mesh` is not null, that the surface's
   * sources lie in it (source_vertex a point id, source_face 4 * cell +
   * face of a cell having those points). The writers call it.
   */
  static femorph::Status Check(const femorph::SurfaceMesh& surface,
    const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh = nullptr);

  /**
   * Adds the mesh arrays listed in the class documentation to `mesh`, the
   * tetrahedral grid the surface was extracted from (cell c = tet c, point i
   * = mesh vertex i, as vtkFEMorphMeshConversion::ToTetMesh builds it).
   * Arrays of the same names already there are replaced.
   */
  static femorph::Status WriteToMesh(const femorph::SurfaceMesh& surface,
    const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh);

  /**
   * Builds the boundary surface with its regions and curves into `output`.
   * `mesh` (may be null): its point data is copied onto the surface points.
   */
  static femorph::Status WriteSurface(const femorph::SurfaceMesh& surface,
    const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh, vtkPolyData* output);

  /// Builds the region table into `output`.
  static femorph::Status WriteRegionTable(
    const femorph::Segmentation& segmentation, vtkTable* output);

  /// What ReadFromMesh() finds on a grid.
  struct MeshSegmentation
  {
    /// Per cell: region of the face opposite local vertex i, -1 interior
    /// (the grid's own local numbering).
    std::vector<femorph::Tet> FaceRegions;
    /// Per point; empty when the grid has no VertexClass array.
    std::vector<std::uint8_t> VertexClasses;
    /// Per region.
    std::vector<femorph::SurfaceType> RegionTypes;
    std::vector<femorph::SurfacePrimitive> RegionSurfaces;
    std::vector<femorph::Convexity> RegionConvexity;
    std::vector<std::array<double, femorph::kRegionParameterWidth>> RegionParameters;
    /// Per curve.
    std::vector<femorph::CurveType> CurveTypes;
    std::vector<std::array<double, femorph::kCurveParameterWidth>> CurveParameters;
    std::vector<bool> CurveClosed;
    std::vector<std::vector<vtkIdType>> CurveVertices; // mesh point ids, in order
    /// Per curve, unpacked: type, fit, regions, continuity, closed, and the
    /// mesh point ids as vertices.
    std::vector<femorph::BoundaryCurve> Curves;
  };

  /**
   * Whether the grid carries any of the segmentation arrays (FaceRegion or a
   * region or curve field array): a grid that does must carry all of them,
   * valid, and ReadFromMesh() says what is wrong otherwise.
   */
  static bool HasSegmentation(vtkUnstructuredGrid* mesh);

  /**
   * Reads the arrays WriteToMesh() writes, each checked for type, number of
   * components and tuples, and value range (region, curve and point ids
   * that name nothing, non-finite fit parameters...). Fails with a message
   * naming the missing or malformed array (a grid named `gridName`, e.g.
   * "the Reference input") and telling the user to run FEMorph Segment;
   * `out` is then empty. VertexClass is optional
   * (TetMesh::classify_vertices() recomputes it from the face regions).
   */
  static femorph::Status ReadFromMesh(
    vtkUnstructuredGrid* mesh, MeshSegmentation& out, const std::string& gridName = "the input");

  /**
   * For a filter that needs a segmentation and got a grid without one
   * (Improve, Deform): segments `mesh` (built from `input`) with FEMorph
   * Segment's default settings, sets its face regions and vertex classes,
   * and returns in `working` a shallow copy of `input` that carries the
   * arrays (read back into `out`). `regionCount` receives the number of
   * regions. Fails with the segmentation's message.
   */
  static femorph::Status SegmentMesh(femorph::TetMesh& mesh, vtkUnstructuredGrid* input,
    vtkSmartPointer<vtkUnstructuredGrid>& working, MeshSegmentation& out, std::size_t& regionCount,
    const std::function<bool(double, const char*)>& progress);

  /**
   * CurveVertices and CurveOffsets in the numbering of `compact`, a mesh
   * edited by a filter: each curve of `curves` (between the regions
   * `curveRegions`) traced again along its regions' shared edges. Returns
   * the traced chains.
   */
  static std::vector<std::vector<femorph::index_t>> WriteTracedCurves(const femorph::CompactMesh& compact,
    const std::vector<femorph::BoundaryCurve>& curves,
    const std::vector<std::array<femorph::index_t, 2>>& curveRegions, vtkFieldData* fd);
};

#endif
