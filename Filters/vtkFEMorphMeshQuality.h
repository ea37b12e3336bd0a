/**
 * @class   vtkFEMorphMeshQuality
 * @brief   element quality of a tetrahedral (or mixed) mesh: stretch, scaled
 *          Jacobian, dihedral angles, inverted elements, and a summary
 *
 * ParaView: "FEMorph Mesh Quality" (menu FEMorph). The diagnosis tool of
 * FEMorph: it accepts any vtkUnstructuredGrid, evaluates the cells it knows,
 * and reports bad ones (inverted, zero volume, low stretch) in arrays and
 * counts instead of refusing them. The measures are computed by
 * femorph_core (Core/quality/tet_quality.h); this class only converts.
 *
 * Input: a vtkUnstructuredGrid. Cells evaluated: VTK_TETRA (all measures),
 * VTK_HEXAHEDRON, VTK_VOXEL (as a hexahedron), VTK_WEDGE and VTK_PYRAMID
 * (scaled Jacobian and Inverted). Other cells (2D, polyhedra, quadratic and
 * higher-order cells...) get NaN and a warning naming their types and counts.
 *
 * Output: a shallow copy of the input (points, cells, point, cell and field
 * data passed through; the input is never modified) with these cell arrays
 * (double unless noted):
 * - `Stretch`: thesis Eq. 1.1, Q = 6 sqrt(6) V / (L_max A) with V the signed
 *   volume, L_max the longest edge and A the total face area. 1 for the
 *   regular tetrahedron, 0 for a flat one, negative when inverted.
 *   Tetrahedra only; NaN for other cells (Eq. 1.1 is defined for tets).
 * - `ScaledJacobian`: thesis Eq. 4.2, the minimum over the corners of
 *   (e1 . (e2 x e3)) / (|e1| |e2| |e3|) with e1, e2, e3 the corner's edges.
 *   1 at the corners of a rectangular box; sqrt(2)/2 for the regular
 *   tetrahedron (Eq. 4.2 is not normalised). Pyramids: the four base corners
 *   only (the apex has four edges; Eq. 4.2 does not define it there).
 *   Negative when a corner is inverted. NaN for cells not evaluated.
 * - `MinDihedralAngle`, `MaxDihedralAngle`: smallest and largest angle
 *   between two faces of a tetrahedron, in degrees (regular tet: 70.53 both;
 *   flat tet: 0 and 180). From the unsigned geometry: an inverted tet gets the
 *   angles of its mirror image. Tetrahedra only; NaN otherwise.
 * - `Inverted` (unsigned char, 0/1): 1 when a tetrahedron has negative volume
 *   (exact orientation test, VTK_TETRA's positive order), or when any corner
 *   of a hexahedron, wedge or pyramid has a negative scaled Jacobian (inverted
 *   or folded). 0 otherwise, and for cells not evaluated.
 * - `Invalid` (unsigned char, 0/1): 1 when the cell is not valid by FEMorph's
 *   one definition, shared with FEMorph Hex To Tet (Core/quality/is_valid_cell.h):
 *   a cell is valid when every tetrahedron over four of its nodes that are not
 *   coplanar in the reference cell has positive volume (exact sign; 1 tet for
 *   a tetrahedron, 4 for a pyramid, 12 for a wedge, 58 for a hexahedron).
 *   Every split into tetrahedra without new points, whatever the diagonals of
 *   its quads, then has only positive tets. Stricter than ScaledJacobian: a
 *   hexahedron whose top face is turned by 90 degrees has ScaledJacobian 0.707
 *   at every corner (VTK's Verdict agrees) but Invalid 1, and Hex To Tet may
 *   report it inverted. Inverted and flat cells are Invalid.
 * Every measure is scale-free: coordinates from 1e-300 to 1e300 give the same
 * values (cells out of the ordinary range are scaled by a power of two first).
 * The output's active cell scalars are set to `Stretch`, so ParaView colours
 * by it.
 *
 * Field data (one tuple each; the input's field data is passed too):
 * - `StretchMin`, `StretchMean`, `StretchMax` (over tetrahedra),
 * - `ScaledJacobianMin`, `ScaledJacobianMean`, `ScaledJacobianMax` (over
 *   evaluated cells),
 * - `MinDihedralAngleMin`, `MinDihedralAngleMean`, `MaxDihedralAngleMean`,
 *   `MaxDihedralAngleMax` (degrees, over tetrahedra),
 * - `StretchThreshold` (the property's value),
 * - vtkIdTypeArray counts: `InvertedCount` (cells with Inverted = 1),
 *   `ZeroVolumeCount` (tetrahedra whose four points are exactly coplanar),
 *   `InvalidCount` (cells with Invalid = 1),
 *   `BelowThresholdCount` (tetrahedra with Stretch < StretchThreshold; inverted
 *   and flat ones included), `TetraCount`, `PyramidCount`, `WedgeCount`,
 *   `HexahedronCount` (hexahedra and voxels), `SkippedCellCount` (cells not
 *   evaluated).
 * Statistics over an empty set are NaN.
 *
 * Distributed (MPI): each process evaluates its piece; ghost cells
 * (vtkGhostType with DUPLICATECELL) get their arrays but are left out of
 * every count and summary, and the summaries are combined over the
 * processes, so every process's field data is the whole mesh's. An empty
 * piece is no error.
 *
 * An input without cells gives an empty output and a warning.
 * NaN or infinite point coordinates are an error (the message gives their
 * count) and produce an empty output.
 *
 * @warning When every tetrahedron has negative volume, the filter warns that
 * the mesh probably uses the opposite vertex order to VTK_TETRA's; the
 * arrays still report them as inverted.
 *
 * @sa vtkMeshQuality (VTK's Verdict-based metrics; its "aspect" measures are
 * not the thesis's stretch).
 */
#ifndef vtkFEMorphMeshQuality_h
#define vtkFEMorphMeshQuality_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

#include <vector> // For std::vector

class FEMORPHFILTERS_EXPORT vtkFEMorphMeshQuality : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphMeshQuality* New();
  vtkTypeMacro(vtkFEMorphMeshQuality, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Tetrahedra with a Stretch below this value are counted in
   * `BelowThresholdCount`. Dimensionless, in [0, 1]. Default 0.05.
   */
  vtkSetClampMacro(StretchThreshold, double, 0.0, 1.0);
  vtkGetMacro(StretchThreshold, double);
  ///@}

protected:
  vtkFEMorphMeshQuality();
  ~vtkFEMorphMeshQuality() override;

  /// Per piece: ghost cells are left out of the counts and summaries, which
  /// CombinePieces() makes global.
  PieceMode GetPieceMode() const override { return PerPiece; }
  void CombinePieces(vtkMultiProcessController* controller, vtkInformationVector* outputVector) override;

  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double StretchThreshold = 0.05;

private:
  /// The last Execute()'s summaries and counts, flattened for the reductions.
  std::vector<double> PieceTotals;

  vtkFEMorphMeshQuality(const vtkFEMorphMeshQuality&) = delete;
  void operator=(const vtkFEMorphMeshQuality&) = delete;
};

#endif
