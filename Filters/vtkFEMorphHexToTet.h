/**
 * @class   vtkFEMorphHexToTet
 * @brief   splits the hexahedra (and wedges and pyramids) of a mesh into
 *          tetrahedra without new vertices, conformingly by default
 *
 * ParaView: "FEMorph Hex To Tet" (menu FEMorph). Thesis 4.4: each hexahedron
 * becomes 5 or 6 tetrahedra by one of the decompositions A to F of Fig. 4.5
 * or their mirror images. The algorithm is femorph_core's
 * decompose_to_tetrahedra() (Core/hex/hex_to_tet.h); this class converts,
 * reports and writes the arrays.
 *
 * Conforming (default): every quad face is split along its diagonal through
 * its smallest point id, the same on both sides, and each hexahedron takes,
 * among the triangulations realising its six diagonals (one or several of
 * the 74 of the cube), the one whose worst tetrahedron has the best stretch
 * (thesis Eq. 1.1). One always exists: the cell's smallest point carries the
 * diagonals of its three faces. Wedges (3 tets) and pyramids (2) follow the
 * same rule; tetrahedra pass through. A quad face already cut by two input
 * tetrahedra (a hex-dominant mesh with tets glued to quads) keeps their
 * diagonal when the cell can realise it. The result is a conforming tet mesh
 * for any conforming input mesh, structured or not.
 *
 * Fixed type (Conforming off): every hexahedron takes DecompositionType
 * (A..F) and Mirrored ("+" or "-") in its own node order, as the thesis does
 * with C+ on structured grids. On a structured grid with aligned node orders
 * C and E conform, A, B, D and F do not (Fig. 4.6); on other meshes any type
 * may conflict. Quad faces split along different diagonals on their two
 * sides are counted and reported by a warning.
 *
 * Input: a vtkUnstructuredGrid of VTK_HEXAHEDRON, VTK_VOXEL (taken in
 * hexahedron node order), VTK_WEDGE, VTK_PYRAMID and VTK_TETRA cells. Any
 * other cell type (2D cells, polyhedra, quadratic and higher-order cells...)
 * is an error naming each type and its count. NaN or infinite coordinates,
 * point ids out of range and cells using one point twice are errors too; an
 * input without cells gives an empty output and a warning (the checks of
 * vtkFEMorphAlgorithm, shared by every FEMorph filter).
 *
 * Output: VTK_TETRA cells over the input's points (the same vtkPoints; no
 * point is added or moved), point data and field data passed through, cell
 * data copied from each tetrahedron's input cell (every child carries its
 * parent's tuple; GlobalIds are not copied, as they would repeat), and:
 * - `SourceCell` (vtkIdType): the input cell each tetrahedron comes from.
 * - `DecompositionType` (signed char): for tetrahedra of a hexahedron the
 *   Fig. 4.5 type, 0..5 for A..F, plus 6 for a mirrored ("-") type in fixed
 *   mode; in conforming mode 0..5 (the type up to the cube's symmetries: "+"
 *   and "-" only mean something in a fixed node order). -1 for tetrahedra of
 *   wedges, pyramids and input tetrahedra.
 * - `Inverted` (unsigned char): 1 for a tetrahedron of zero or negative
 *   volume (exact orientation test), else 0.
 * - field data `NonConformingFaceCount` and `InvertedCellCount`
 *   (vtkIdTypeArray, one tuple each).
 *
 * Inverted output: when some input cell gives a tetrahedron of zero or
 * negative volume (an inverted or badly distorted cell: in conforming mode
 * every realising triangulation has one), the filter stops with an error
 * naming how many and which cells, and the output is empty, unless
 * AllowInverted is on: then it warns and marks them in `Inverted`.
 *
 * Valid cells: FEMorph has one definition, shared with FEMorph Mesh Quality's
 * `Invalid` flag (Core/quality/is_valid_cell.h): a cell is valid when every
 * tetrahedron over four of its nodes that are not coplanar in the reference
 * cell (58 for a hexahedron, 12 for a wedge, 4 for a pyramid) has positive
 * volume. A valid cell never gives an inverted tetrahedron here, whatever the
 * diagonals; a cell reported inverted is always Invalid in Mesh Quality,
 * while an Invalid cell may split positively with the diagonals it gets. The
 * corner scaled Jacobian is a weaker test: a hexahedron whose top face is
 * turned by 90 degrees has 0.707 at every corner but is invalid.
 *
 * The input is never modified.
 *
 * @sa vtkFEMorphMeshQuality (to check the result), vtkTetrahedralize
 * (VTK's; no choice of diagonals)
 */
#ifndef vtkFEMorphHexToTet_h
#define vtkFEMorphHexToTet_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

class FEMORPHFILTERS_EXPORT vtkFEMorphHexToTet : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphHexToTet* New();
  vtkTypeMacro(vtkFEMorphHexToTet, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Thesis Fig. 4.5 types; the values of DecompositionType.
  enum DecompositionTypes
  {
    TYPE_A = 0,
    TYPE_B = 1,
    TYPE_C = 2,
    TYPE_D = 3,
    TYPE_E = 4,
    TYPE_F = 5
  };

  ///@{
  /**
   * Conforming decomposition: every quad split along its diagonal through its
   * smallest point id on both sides, each hexahedron by the best-stretch
   * triangulation realising its diagonals. Off: DecompositionType and
   * Mirrored in every hexahedron's own node order. Default on.
   */
  vtkSetMacro(Conforming, vtkTypeBool);
  vtkGetMacro(Conforming, vtkTypeBool);
  vtkBooleanMacro(Conforming, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Fixed type of Fig. 4.5 when Conforming is off: TYPE_A (5 tets) to TYPE_F
   * (6 tets), in [0, 5]. Default TYPE_C (the thesis' choice).
   */
  vtkSetClampMacro(DecompositionType, int, TYPE_A, TYPE_F);
  vtkGetMacro(DecompositionType, int);
  ///@}

  ///@{
  /**
   * Use the mirrored ("-") variant of DecompositionType when Conforming is
   * off: its mirror image in the plane between nodes 0-3-7-4 and 1-2-6-5.
   * Default off ("+").
   */
  vtkSetMacro(Mirrored, vtkTypeBool);
  vtkGetMacro(Mirrored, vtkTypeBool);
  vtkBooleanMacro(Mirrored, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Produce the output even when some tetrahedra have zero or negative
   * volume, with a warning and the `Inverted` cell array marking them. Off:
   * such input is an error and the output is empty. Default off.
   */
  vtkSetMacro(AllowInverted, vtkTypeBool);
  vtkGetMacro(AllowInverted, vtkTypeBool);
  vtkBooleanMacro(AllowInverted, vtkTypeBool);
  ///@}

protected:
  vtkFEMorphHexToTet();
  ~vtkFEMorphHexToTet() override;

  /// Gathered on process 0: each quad's diagonal follows its global point ids.
  PieceMode GetPieceMode() const override { return Gathered; }

  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  // Defaults: femorph::HexToTetParams (set in the constructor).
  vtkTypeBool Conforming;
  int DecompositionType;
  vtkTypeBool Mirrored;
  vtkTypeBool AllowInverted = 0;

private:
  vtkFEMorphHexToTet(const vtkFEMorphHexToTet&) = delete;
  void operator=(const vtkFEMorphHexToTet&) = delete;
};

#endif
