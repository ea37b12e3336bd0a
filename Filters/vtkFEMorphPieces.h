/**
 * @class   vtkFEMorphPieces
 * @brief   the pieces of a distributed grid brought together on one process
 *
 * Under MPI (pvbatch, pvserver) each process holds a piece of the input,
 * possibly with a layer of ghost cells (vtkGhostType with DUPLICATECELL, as
 * D3 and RedistributeDataSet make them). The filters that need the whole
 * mesh (vtkFEMorphAlgorithm's Gathered mode, docs/ARCHITECTURE.md "Parallel
 * runs") gather the pieces to process 0 with these helpers:
 *
 * - DropGhostCells(): a piece without its ghost cells and the points only
 *   they use;
 * - MergePieces(): one grid from pieces. Ghost cells are dropped and the
 *   points shared by pieces merged: by global point id (vtkGlobalPointIds or
 *   the point data's global ids) when every piece with cells has them, else
 *   by equal coordinates (within a piece, points stay distinct: an unmerged
 *   seam stays unmerged). Cells come in global cell id order when every
 *   piece with cells has global cell ids (a cell found twice is kept once),
 *   else in piece order; points in global point id order when there are
 *   global point ids, else in their first use by the cells. With ids taken
 *   from the serial mesh this is the serial mesh itself. The global id and
 *   ghost arrays are not carried over (they describe the distribution);
 *   the other point and cell arrays the pieces share are.
 * - Gather(): collective; every process's piece, ghost cells dropped, to
 *   process 0, merged there. The other processes get null.
 * - AddGlobalIds(): vtkGlobalPointIds and vtkGlobalCellIds (0..n-1) on a
 *   data set that has none.
 *
 * C++ only (not wrapped).
 */
#ifndef vtkFEMorphPieces_h
#define vtkFEMorphPieces_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkSmartPointer.h"      // For vtkSmartPointer

#include <vector> // For std::vector

class vtkDataSet;
class vtkMultiProcessController;
class vtkUnstructuredGrid;

class FEMORPHFILTERS_EXPORT vtkFEMorphPieces
{
public:
  /// `grid` without ghost cells (the same grid when it has none).
  static vtkSmartPointer<vtkUnstructuredGrid> DropGhostCells(vtkUnstructuredGrid* grid);

  /// One grid from `pieces` (null entries count as empty pieces).
  static vtkSmartPointer<vtkUnstructuredGrid> MergePieces(
    const std::vector<vtkUnstructuredGrid*>& pieces);

  /// Collective over `controller`: the merged grid on process 0, null on the
  /// others. `piece` may be null (an empty piece).
  static vtkSmartPointer<vtkUnstructuredGrid> Gather(
    vtkMultiProcessController* controller, vtkUnstructuredGrid* piece);

  /// Global point and cell ids 0..n-1 unless `data` has them.
  static void AddGlobalIds(vtkDataSet* data);
};

#endif
