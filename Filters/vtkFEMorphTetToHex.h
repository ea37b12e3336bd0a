/**
 * @class   vtkFEMorphTetToHex
 * @brief   recombines the tetrahedra of a mesh into hexahedra, prisms and
 *          pyramids (hex-dominant mesh)
 *
 * ParaView: "FEMorph Tet To Hex" (menu FEMorph). Thesis 4.5 (after Meshkat &
 * Talmor 2000 and Botella 2016): the local search A1 finds every group of
 * 5 or 6 tetrahedra forming a hexahedron (the decomposition types A-F of
 * Fig. 4.5), 3 forming a prism and 2 forming a pyramid, whose quad faces
 * are flat within the Quad Angle (QUAD of 4.5.3); the greedy conversion A2
 * adopts them by the priority of Eq. 4.1 (hexahedra first, then prisms,
 * then pyramids; flatter, squarer quads first) while their tetrahedra are
 * free. No point is added or moved. The algorithm is femorph_core's
 * recombine_tetrahedra() (Core/hex/tet_to_hex.h).
 *
 * Input: a vtkUnstructuredGrid of VTK_TETRA cells only (other cell types
 * are an error naming each type and its count), positively oriented
 * (VTK_TETRA's order) and conforming. Inverted or flat tetrahedra, faces
 * shared by more than two tetrahedra and NaN coordinates are errors. An
 * input without cells gives an empty output and a warning. The input is
 * never modified.
 *
 * Output: a vtkUnstructuredGrid with the input's points and point data, and
 * cells VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID (in this order) and then the
 * VTK_TETRA left over (in input order), all of positive volume in VTK's node
 * orders. Cell data: the input's cell arrays, each cell taking the values of
 * its first (smallest-id) source tetrahedron; `ScaledJacobian` (double,
 * thesis Eq. 4.2, minimum over the corners; pyramids over their base
 * corners); `SourceTets` (int, the number of input tetrahedra of the cell).
 * Field data (the input's, plus one tuple each, Table 4.3's layout):
 * `HexCount`, `PrismCount`, `PyramidCount`, `TetCount` (vtkIdTypeArray),
 * `HexCountRatio` ... `TetCountRatio`, `HexVolume` ... `TetVolume`,
 * `HexVolumeRatio` ... `TetVolumeRatio`, `TotalVolume` (double);
 * `CandidateCounts` and `AdmissibleCandidateCounts` (3 components: hexahedra,
 * prisms, pyramids found by A1, and those reaching the minimum scaled
 * Jacobian); `NonConformalInterfaces` (quad faces meeting two triangles of
 * other cells); `DissolvedNonConformal`; `TetToHexTimes` (seconds: checks,
 * search, adoption, total).
 *
 * @warning Hexahedra next to tetrahedra are non-conformal (their quad meets
 * two triangles); RefuseNonConformal removes them, at the cost of many
 * hexahedra on distorted meshes.
 *
 * @sa vtkFEMorphMeshQuality
 */
#ifndef vtkFEMorphTetToHex_h
#define vtkFEMorphTetToHex_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

class FEMORPHFILTERS_EXPORT vtkFEMorphTetToHex : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphTetToHex* New();
  vtkTypeMacro(vtkFEMorphTetToHex, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * QUAD (thesis 4.5.3): two triangles form a quad face of a candidate when
   * their normals differ by at most this angle (delta_angle = cos of it).
   * Larger values give more hexahedra of lower quality (Table 4.3).
   * Degrees, in [0, 180]. Default 20.
   */
  vtkSetClampMacro(QuadAngle, double, 0.0, 180.0);
  vtkGetMacro(QuadAngle, double);
  ///@}

  ///@{
  /**
   * Beyond the thesis: a candidate is adopted only when its minimum scaled
   * Jacobian (Eq. 4.2) reaches this value; 0 or more keeps inverted cells
   * out. In [-1, 1]. Default 0.2.
   */
  vtkSetClampMacro(MinScaledJacobian, double, -1.0, 1.0);
  vtkGetMacro(MinScaledJacobian, double);
  ///@}

  ///@{
  /**
   * Which cells to recombine: hexahedra (5 or 6 tetrahedra), prisms (3),
   * pyramids (2). Default all on.
   */
  vtkSetMacro(Hexahedra, vtkTypeBool);
  vtkGetMacro(Hexahedra, vtkTypeBool);
  vtkBooleanMacro(Hexahedra, vtkTypeBool);
  vtkSetMacro(Prisms, vtkTypeBool);
  vtkGetMacro(Prisms, vtkTypeBool);
  vtkBooleanMacro(Prisms, vtkTypeBool);
  vtkSetMacro(Pyramids, vtkTypeBool);
  vtkGetMacro(Pyramids, vtkTypeBool);
  vtkBooleanMacro(Pyramids, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Leave no non-conformal interface: cells with a quad face meeting two
   * triangles are capped by a pyramid when one fits, otherwise dissolved
   * back into tetrahedra. Default off.
   */
  vtkSetMacro(RefuseNonConformal, vtkTypeBool);
  vtkGetMacro(RefuseNonConformal, vtkTypeBool);
  vtkBooleanMacro(RefuseNonConformal, vtkTypeBool);
  ///@}

protected:
  vtkFEMorphTetToHex();
  ~vtkFEMorphTetToHex() override;

  /// Gathered on process 0: the recombination is one greedy over the whole mesh.
  PieceMode GetPieceMode() const override { return Gathered; }

  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double QuadAngle = 20.0;
  double MinScaledJacobian = 0.2;
  vtkTypeBool Hexahedra = 1;
  vtkTypeBool Prisms = 1;
  vtkTypeBool Pyramids = 1;
  vtkTypeBool RefuseNonConformal = 0;

private:
  vtkFEMorphTetToHex(const vtkFEMorphTetToHex&) = delete;
  void operator=(const vtkFEMorphTetToHex&) = delete;
};

#endif
