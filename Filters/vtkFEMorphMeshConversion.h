/**
 * @class   vtkFEMorphMeshConversion
 * @brief   vtkUnstructuredGrid <-> femorph::TetMesh, shared by every FEMorph filter
 *
 * Static helpers, no state. Every filter that edits the mesh goes through
 * them, so the attribute policy is the same everywhere:
 *
 * - ToTetMesh() accepts VTK_TETRA cells only (any other cell type is an error
 *   naming each type and its count), rejects NaN or infinite coordinates,
 *   passes a 4-component cell array `FaceRegion` (region id of the face
 *   opposite local vertex i, -1 = none) to the core, and forwards the core's
 *   message when TetMesh::build() refuses the mesh (mixed orientation,
 *   non-manifold, inverted or zero-volume tets...). Points no tet uses are
 *   dropped with a warning.
 * - FromCompactMesh() writes the core mesh back: double points, VTK_TETRA
 *   cells, point data interpolated onto every output vertex with the core's
 *   vertex stencils (an unchanged vertex copies its tuple exactly), cell data
 *   copied from the input tet each output tet descends from (children of a
 *   split tet carry their parent's values), field data passed. It adds the
 *   cell array `FaceRegion` (int, 4 components; written when any face has a
 *   region or the input had the array) and the point array `VertexClass`
 *   (unsigned char: 0 inner, 1 surface, 2 curve, 3 corner).
 *
 * Messages are returned, not printed: the calling filter reports them with
 * vtkErrorMacro / vtkWarningMacro so they carry the filter's name.
 *
 * @warning GlobalIds and PedigreeIds point arrays are not interpolated (VTK's
 * InterpolateAllocate policy: ids of input entities mean nothing on new ones).
 * The input's own `FaceRegion` and `VertexClass` arrays are replaced by the
 * ones computed from the core mesh.
 *
 * This header names core types, so it is private to the module (not wrapped).
 */
#ifndef vtkFEMorphMeshConversion_h
#define vtkFEMorphMeshConversion_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkType.h"            // For vtkIdType

#include "common/types.h" // femorph::Status
#include "mesh/tet_mesh.h" // femorph::TetMesh, CompactMesh, BuildOptions

#include <array>
#include <string>
#include <vector>

class vtkPoints;
class vtkUnstructuredGrid;

class FEMORPHFILTERS_EXPORT vtkFEMorphMeshConversion
{
public:
  /// Name of the cell array holding the region id of each tet face.
  static constexpr const char* FaceRegionName = "FaceRegion";
  /// Name of the point array holding the vertex class.
  static constexpr const char* VertexClassName = "VertexClass";

  /**
   * Builds `mesh` from `input`. `filterLabel` starts the messages, e.g.
   * "FEMorph Improve". On failure the status names the problem and `mesh` is
   * left empty; warnings (dropped points, malformed FaceRegion) are appended
   * to `warnings` when not null. `options.face_regions` is filled from the
   * FaceRegion array when present; the other options are the caller's.
   */
  static femorph::Status ToTetMesh(vtkUnstructuredGrid* input, const std::string& filterLabel,
    femorph::BuildOptions options, femorph::TetMesh& mesh,
    femorph::BuildReport* report = nullptr, std::vector<std::string>* warnings = nullptr);

  /**
   * Writes `mesh` into `output` with `input`'s attributes carried over (see
   * the class documentation). `input` must be the grid `mesh` was built from
   * (stencil and origin ids refer to its points and cells).
   */
  static void FromCompactMesh(const femorph::CompactMesh& mesh, vtkUnstructuredGrid* input,
    vtkUnstructuredGrid* output);

  /**
   * The VTK name of a cell type, e.g. "VTK_HEXAHEDRON"; "cell type <n>" for
   * types this table does not know.
   */
  static std::string CellTypeName(int cellType);

  /**
   * Lists cell counts by type: counts[t] cells of VTK type t, e.g.
   * "120 VTK_HEXAHEDRON and 4 VTK_WEDGE cells" (types in VTK's numbering
   * order). Empty when all counts are 0.
   */
  static std::string DescribeCellCounts(const std::array<vtkIdType, 256>& counts);

  /**
   * Counts the cells of `input` whose type is not `acceptedType` and lists
   * them by type, e.g. "120 VTK_HEXAHEDRON and 4 VTK_WEDGE cells". Returns
   * the count; `description` is empty when it is 0.
   */
  static vtkIdType DescribeOtherCells(
    vtkUnstructuredGrid* input, int acceptedType, std::string& description);

  /// Number of points with a NaN or infinite coordinate.
  static vtkIdType CountNonFinitePoints(vtkPoints* points);
};

#endif
