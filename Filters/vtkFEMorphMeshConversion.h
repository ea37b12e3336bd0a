/**
 * @class   vtkFEMorphMeshConversion
 * @brief   vtkUnstructuredGrid <-> femorph_core's meshes, shared by every
 *          FEMorph filter through vtkFEMorphAlgorithm
 *
 * Static helpers, no state, so the checks and the attribute policy are the
 * same in every filter:
 *
 * - CheckGrid() is the one set of input checks (points present and finite,
 *   the cell types a filter reads, attribute arrays exactly as long as the
 *   points or cells, the point count of every cell, point ids
 *   in range, sizes within the core's 32-bit ids). The readers below expect
 *   a grid that passed it (ToTetMesh() checks again: tests call it alone).
 * - ReadPoints(), ReadTetGrid(), ReadLinearCells() copy the geometry into
 *   the core's arrays (voxels as hexahedra).
 * - ToTetMesh() builds a femorph::TetMesh; the face regions are the
 *   caller's (BuildOptions::face_regions, e.g. from
 *   vtkFEMorphSegmentationArrays::ReadFromMesh, which validates them). It
 *   forwards the core's message when TetMesh::build() refuses the mesh
 *   (mixed orientation, non-manifold, inverted or zero-volume tets...).
 *   Points no tet uses are dropped with a warning.
 * - FromCompactMesh() writes the core mesh back: double points, VTK_TETRA
 *   cells, point data interpolated onto every output vertex with the core's
 *   vertex stencils (an unchanged vertex copies its tuple exactly), cell data
 *   copied from the input tet each output tet descends from (children of a
 *   split tet carry their parent's values), field data passed. It adds the
 *   cell array `FaceRegion` (int, 4 components; written when any face has a
 *   region or the input had the array) and the point array `VertexClass`
 *   (unsigned char: 0 inner, 1 surface, 2 curve, 3 corner).
 * - SetTetCells(), SetMixedCells() and CopySourceCellData() write new cells
 *   over the input's points, each taking the cell data of its source cell
 *   (Hex To Tet, Tet To Hex).
 *
 * Messages are returned, not printed, and do not name the filter: the
 * calling filter reports them (vtkFEMorphAlgorithm::Fail / Warn).
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
#include "vtkSmartPointer.h"    // For vtkSmartPointer
#include "vtkType.h"            // For vtkIdType

#include "common/types.h"     // femorph::Status, Vec3, Tet
#include "hex/mixed_cells.h"    // femorph::MixedCells
#include "mesh/tet_mesh.h"      // femorph::TetMesh, CompactMesh, BuildOptions

#include <array>
#include <cstdint>
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

  /// The cells a filter reads (vtkFEMorphAlgorithm::InputCells).
  enum class CellSet
  {
    Tetrahedra,
    Linear3D,
    Any
  };

  /**
   * The input checks every filter makes, in this order: points present when
   * there are cells; sizes within the core's ids; finite coordinates; cell
   * types in `cells`; every point and cell array as long as the points or
   * cells; every cell of a VTK type (a number that is none is an error)
   * with the number of points its type has, when the type has a fixed one;
   * point ids in range. Returns an empty string when the grid
   * passes, else the message, naming the grid as `gridName` (e.g. "the
   * Reference input").
   */
  static std::string CheckGrid(
    vtkUnstructuredGrid* grid, CellSet cells, const std::string& gridName = "the input");

  ///@{
  /// The grid's points as the core's positions, and back (double).
  static std::vector<femorph::Vec3> ReadPoints(vtkUnstructuredGrid* grid);
  static vtkSmartPointer<vtkPoints> NewPoints(const std::vector<femorph::Vec3>& points);
  ///@}

  /// Points and tetrahedra of a grid of VTK_TETRA cells (fails with
  /// CheckGrid's message otherwise).
  static femorph::Status ReadTetGrid(
    vtkUnstructuredGrid* grid, std::vector<femorph::Vec3>& points, std::vector<femorph::Tet>& tets);

  /**
   * The linear 3D cells of `grid` (tetrahedra, pyramids, wedges, hexahedra,
   * voxels as hexahedra in VTK_HEXAHEDRON's node order) into `cells`;
   * `cellIds` (may be null) receives the grid's id of each. Other cells are
   * skipped and counted by type in `skipped` (may be null). Expects a grid
   * that passed CheckGrid().
   */
  static void ReadLinearCells(vtkUnstructuredGrid* grid, femorph::MixedCells& cells,
    std::vector<vtkIdType>* cellIds = nullptr, std::array<vtkIdType, 256>* skipped = nullptr);

  /**
   * The cell array `name` of `grid` as a mask (1 where nonzero), e.g. the
   * cells Improve's RegionArrayName selects: a numeric array with one
   * component and one finite value per cell. Fails with a message naming
   * the array (as `property` 'name') and what is wrong; `mask` is then
   * empty.
   */
  static femorph::Status ReadCellMask(vtkUnstructuredGrid* grid, const std::string& name,
    const std::string& property, std::vector<std::uint8_t>& mask);

  /**
   * The cell array `name` of `grid` as ids (e.g. material ids): an integer
   * array (not float, not string) with one component, one value per cell,
   * every value in [0, INT_MAX]. Fails with a message naming the array (as
   * `property` 'name') and what is wrong, the first offending cell for a
   * value; `ids` is then empty.
   */
  static femorph::Status ReadCellIds(vtkUnstructuredGrid* grid, const std::string& name,
    const std::string& property, std::vector<int>& ids);

  /**
   * Point data of `output` (with its points set, one per stencil) from
   * `input`'s: point i takes the weighted sum of the tuples of its stencil's
   * input points (ids -1 unused); a point that is one input point copies its
   * tuple exactly; integer and non-numeric arrays (named ones: they are
   * paired with the input's by name) take the tuple of the largest weight,
   * since an id or a label has no mean. GlobalIds and
   * PedigreeIds are left out (as InterpolateAllocate does).
   */
  static void InterpolatePointData(vtkUnstructuredGrid* input,
    const std::vector<femorph::VertexStencil>& stencils, vtkUnstructuredGrid* output);

  /**
   * Builds `mesh` from `input` (tetrahedra only) with `options`. On failure
   * the status names the problem and `mesh` is left empty; warnings
   * (dropped points) are appended to `warnings` when not null.
   */
  static femorph::Status ToTetMesh(vtkUnstructuredGrid* input, const femorph::BuildOptions& options,
    femorph::TetMesh& mesh, femorph::BuildReport* report = nullptr,
    std::vector<std::string>* warnings = nullptr);

  /**
   * Writes `mesh` into `output` with `input`'s attributes carried over (see
   * the class documentation). `input` must be the grid `mesh` was built from
   * (stencil and origin ids refer to its points and cells).
   */
  static void FromCompactMesh(const femorph::CompactMesh& mesh, vtkUnstructuredGrid* input,
    vtkUnstructuredGrid* output);

  ///@{
  /// `output`'s cells: VTK_TETRA cells, or the cells of `cells` (VTK's node
  /// orders), over the points the caller sets.
  static void SetTetCells(vtkUnstructuredGrid* output, const std::vector<femorph::Tet>& tets);
  static void SetMixedCells(vtkUnstructuredGrid* output, const femorph::MixedCells& cells);
  ///@}

  /**
   * Cell data of `output` (with its cells set): cell c takes the tuple of
   * `input`'s cell `source[c]` (null values for an id out of range).
   */
  static void CopySourceCellData(
    vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, const std::vector<femorph::index_t>& source);

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
