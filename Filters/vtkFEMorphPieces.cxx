#include "vtkFEMorphPieces.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace
{
constexpr const char* GlobalPointIdsName = "vtkGlobalPointIds";
constexpr const char* GlobalCellIdsName = "vtkGlobalCellIds";

// The global ids of `dsa` (its attribute, else the array VTK names so), or null.
vtkDataArray* GlobalIds(vtkDataSetAttributes* dsa, const char* name)
{
  vtkDataArray* ids = dsa->GetGlobalIds();
  return ids ? ids : dsa->GetArray(name);
}

bool IsGhost(vtkUnsignedCharArray* ghosts, vtkIdType cell)
{
  return ghosts && (ghosts->GetValue(cell) & vtkDataSetAttributes::DUPLICATECELL) != 0;
}

// The arrays that describe the distribution, not the mesh.
void RemoveDistributionArrays(vtkUnstructuredGrid* grid)
{
  for (vtkDataSetAttributes* dsa :
    { static_cast<vtkDataSetAttributes*>(grid->GetPointData()),
      static_cast<vtkDataSetAttributes*>(grid->GetCellData()) })
  {
    dsa->RemoveArray(vtkDataSetAttributes::GhostArrayName());
    dsa->RemoveArray(GlobalPointIdsName);
    dsa->RemoveArray(GlobalCellIdsName);
  }
}

// Appends cell `c` of `in` to `out` with its points renumbered by `map`
// (a polyhedron's face stream too); `ids` and `faces` are scratch lists.
vtkIdType InsertRenumberedCell(vtkUnstructuredGrid* in, vtkIdType c, const std::vector<vtkIdType>& map,
  vtkIdList* ids, vtkIdList* faces, vtkUnstructuredGrid* out)
{
  in->GetCellPoints(c, ids);
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
  {
    ids->SetId(k, map[static_cast<std::size_t>(ids->GetId(k))]);
  }
  const int type = in->GetCellType(c);
  if (type != VTK_POLYHEDRON)
  {
    return out->InsertNextCell(type, ids);
  }
  // Face stream: nfaces, then per face its point count and points.
  in->GetFaceStream(c, faces);
  const vtkIdType nfaces = faces->GetNumberOfIds() > 0 ? faces->GetId(0) : 0;
  std::vector<vtkIdType> stream;
  for (vtkIdType i = 1, f = 0; f < nfaces; ++f)
  {
    const vtkIdType n = faces->GetId(i++);
    stream.push_back(n);
    for (vtkIdType k = 0; k < n; ++k)
    {
      stream.push_back(map[static_cast<std::size_t>(faces->GetId(i++))]);
    }
  }
  return out->InsertNextCell(type, ids->GetNumberOfIds(), ids->GetPointer(0), nfaces, stream.data());
}

// A cell of a piece in the merged grid's order.
struct CellRef
{
  int Piece;
  vtkIdType Cell;
};
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> vtkFEMorphPieces::DropGhostCells(vtkUnstructuredGrid* grid)
{
  vtkUnsignedCharArray* ghosts = grid->GetCellGhostArray();
  const vtkIdType numCells = grid->GetNumberOfCells();
  vtkIdType kept = 0;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    kept += IsGhost(ghosts, c) ? 0 : 1;
  }
  if (kept == numCells)
  {
    return grid;
  }
  // Keep the piece's own point identities (no merging here), only the points
  // the remaining cells use, in their original order.
  std::vector<vtkIdType> pointMap(static_cast<std::size_t>(grid->GetNumberOfPoints()), -1);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    if (IsGhost(ghosts, c))
    {
      continue;
    }
    grid->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      pointMap[static_cast<std::size_t>(ids->GetId(k))] = 0;
    }
  }
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(grid->GetPoints()->GetDataType());
  vtkPointData* inPD = grid->GetPointData();
  vtkPointData* outPD = out->GetPointData();
  // Global ids are not copied by default: MergePieces() needs them.
  outPD->CopyGlobalIdsOn();
  outPD->CopyAllocate(inPD);
  vtkIdType next = 0;
  for (std::size_t p = 0; p < pointMap.size(); ++p)
  {
    if (pointMap[p] == 0)
    {
      pointMap[p] = next;
      points->InsertNextPoint(grid->GetPoint(static_cast<vtkIdType>(p)));
      outPD->CopyData(inPD, static_cast<vtkIdType>(p), next);
      ++next;
    }
  }
  out->SetPoints(points);
  out->Allocate(kept);
  vtkCellData* inCD = grid->GetCellData();
  vtkCellData* outCD = out->GetCellData();
  outCD->CopyGlobalIdsOn();
  outCD->CopyAllocate(inCD, kept);
  vtkNew<vtkIdList> faces;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    if (IsGhost(ghosts, c))
    {
      continue;
    }
    const vtkIdType newId = InsertRenumberedCell(grid, c, pointMap, ids, faces, out);
    outCD->CopyData(inCD, c, newId);
  }
  out->GetFieldData()->ShallowCopy(grid->GetFieldData());
  out->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  return out;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> vtkFEMorphPieces::MergePieces(
  const std::vector<vtkUnstructuredGrid*>& input)
{
  // Each piece without its ghost cells; the pieces with cells take part.
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> pieces;
  for (vtkUnstructuredGrid* grid : input)
  {
    if (grid && grid->GetNumberOfCells() > 0)
    {
      vtkSmartPointer<vtkUnstructuredGrid> piece = DropGhostCells(grid);
      if (piece->GetNumberOfCells() > 0)
      {
        pieces.push_back(piece);
      }
    }
  }
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (pieces.empty())
  {
    for (vtkUnstructuredGrid* grid : input)
    {
      if (grid)
      {
        out->GetFieldData()->ShallowCopy(grid->GetFieldData());
        break;
      }
    }
    return out;
  }
  const int numPieces = static_cast<int>(pieces.size());
  bool byPointId = true, byCellId = true;
  for (const auto& piece : pieces)
  {
    byPointId = byPointId && GlobalIds(piece->GetPointData(), GlobalPointIdsName);
    byCellId = byCellId && GlobalIds(piece->GetCellData(), GlobalCellIdsName);
  }

  // Cell order: global cell id (each id once), else piece by piece.
  std::vector<CellRef> cells;
  if (byCellId)
  {
    std::vector<std::pair<vtkIdType, CellRef>> keyed;
    for (int p = 0; p < numPieces; ++p)
    {
      vtkDataArray* ids = GlobalIds(pieces[p]->GetCellData(), GlobalCellIdsName);
      for (vtkIdType c = 0; c < pieces[p]->GetNumberOfCells(); ++c)
      {
        keyed.push_back({ static_cast<vtkIdType>(ids->GetComponent(c, 0)), { p, c } });
      }
    }
    std::stable_sort(keyed.begin(), keyed.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t i = 0; i < keyed.size(); ++i)
    {
      if (i == 0 || keyed[i].first != keyed[i - 1].first)
      {
        cells.push_back(keyed[i].second);
      }
    }
  }
  else
  {
    for (int p = 0; p < numPieces; ++p)
    {
      for (vtkIdType c = 0; c < pieces[p]->GetNumberOfCells(); ++c)
      {
        cells.push_back({ p, c });
      }
    }
  }

  // Each piece's points to merged points, in their first use by the cells.
  std::vector<std::vector<vtkIdType>> pointMap(pieces.size());
  for (int p = 0; p < numPieces; ++p)
  {
    pointMap[p].assign(static_cast<std::size_t>(pieces[p]->GetNumberOfPoints()), -1);
  }
  std::vector<std::pair<int, vtkIdType>> merged; // (piece, point) of each merged point
  std::vector<vtkIdType> mergedKey;              // its global id (byPointId)
  std::unordered_map<vtkIdType, vtkIdType> byId;
  // Coordinates -> the merged points there, in creation order; the k-th
  // distinct point of a piece at those coordinates is the k-th merged one.
  std::map<std::array<double, 3>, std::vector<vtkIdType>> byCoords;
  std::vector<std::map<std::array<double, 3>, std::size_t>> usedAt(pieces.size());
  vtkNew<vtkIdList> ids;
  for (const CellRef& ref : cells)
  {
    vtkUnstructuredGrid* piece = pieces[ref.Piece];
    piece->GetCellPoints(ref.Cell, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const vtkIdType local = ids->GetId(k);
      vtkIdType& target = pointMap[ref.Piece][static_cast<std::size_t>(local)];
      if (target >= 0)
      {
        continue;
      }
      if (byPointId)
      {
        const auto key = static_cast<vtkIdType>(
          GlobalIds(piece->GetPointData(), GlobalPointIdsName)->GetComponent(local, 0));
        auto it = byId.find(key);
        if (it == byId.end())
        {
          it = byId.emplace(key, static_cast<vtkIdType>(merged.size())).first;
          merged.push_back({ ref.Piece, local });
          mergedKey.push_back(key);
        }
        target = it->second;
      }
      else
      {
        std::array<double, 3> x;
        piece->GetPoint(local, x.data());
        std::vector<vtkIdType>& there = byCoords[x];
        const std::size_t k2 = usedAt[ref.Piece][x]++;
        if (k2 == there.size())
        {
          there.push_back(static_cast<vtkIdType>(merged.size()));
          merged.push_back({ ref.Piece, local });
        }
        target = there[k2];
      }
    }
  }
  // Global point id order: renumber the merged points.
  if (byPointId)
  {
    std::vector<vtkIdType> order(merged.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
      [&](vtkIdType a, vtkIdType b) { return mergedKey[a] < mergedKey[b]; });
    std::vector<vtkIdType> rank(merged.size());
    std::vector<std::pair<int, vtkIdType>> sorted(merged.size());
    for (std::size_t i = 0; i < order.size(); ++i)
    {
      rank[static_cast<std::size_t>(order[i])] = static_cast<vtkIdType>(i);
      sorted[i] = merged[static_cast<std::size_t>(order[i])];
    }
    merged.swap(sorted);
    for (auto& map : pointMap)
    {
      for (vtkIdType& id : map)
      {
        id = id >= 0 ? rank[static_cast<std::size_t>(id)] : id;
      }
    }
  }

  // Points, cells and the arrays every piece has.
  vtkDataSetAttributes::FieldList pointFields(numPieces), cellFields(numPieces);
  for (const auto& piece : pieces)
  {
    pointFields.IntersectFieldList(piece->GetPointData());
    cellFields.IntersectFieldList(piece->GetCellData());
  }
  vtkNew<vtkPoints> points;
  points->SetDataType(pieces[0]->GetPoints()->GetDataType());
  points->SetNumberOfPoints(static_cast<vtkIdType>(merged.size()));
  vtkPointData* outPD = out->GetPointData();
  outPD->CopyAllocate(pointFields, static_cast<vtkIdType>(merged.size()));
  for (std::size_t i = 0; i < merged.size(); ++i)
  {
    vtkUnstructuredGrid* piece = pieces[merged[i].first];
    points->SetPoint(static_cast<vtkIdType>(i), piece->GetPoint(merged[i].second));
    outPD->CopyData(pointFields, piece->GetPointData(), merged[i].first, merged[i].second,
      static_cast<vtkIdType>(i));
  }
  out->SetPoints(points);
  out->Allocate(static_cast<vtkIdType>(cells.size()));
  vtkCellData* outCD = out->GetCellData();
  outCD->CopyAllocate(cellFields, static_cast<vtkIdType>(cells.size()));
  vtkNew<vtkIdList> faces;
  for (const CellRef& ref : cells)
  {
    vtkUnstructuredGrid* piece = pieces[ref.Piece];
    const std::vector<vtkIdType>& map = pointMap[ref.Piece];
    const vtkIdType newId = InsertRenumberedCell(piece, ref.Cell, map, ids, faces, out);
    outCD->CopyData(cellFields, piece->GetCellData(), ref.Piece, ref.Cell, newId);
  }
  out->GetFieldData()->ShallowCopy(pieces[0]->GetFieldData());
  RemoveDistributionArrays(out);
  return out;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> vtkFEMorphPieces::Gather(
  vtkMultiProcessController* controller, vtkUnstructuredGrid* piece)
{
  // Ghost cells stay home: they are another piece's own cells.
  vtkSmartPointer<vtkUnstructuredGrid> send =
    piece ? DropGhostCells(piece) : vtkSmartPointer<vtkUnstructuredGrid>::New();
  std::vector<vtkSmartPointer<vtkDataObject>> received;
  controller->Gather(send, received, 0);
  if (controller->GetLocalProcessId() != 0)
  {
    return nullptr;
  }
  std::vector<vtkUnstructuredGrid*> pieces;
  for (const auto& object : received)
  {
    pieces.push_back(vtkUnstructuredGrid::SafeDownCast(object));
  }
  return MergePieces(pieces);
}

//------------------------------------------------------------------------------
void vtkFEMorphPieces::AddGlobalIds(vtkDataSet* data)
{
  if (!data)
  {
    return;
  }
  auto add = [](vtkDataSetAttributes* dsa, const char* name, vtkIdType n) {
    if (GlobalIds(dsa, name))
    {
      return;
    }
    vtkNew<vtkIdTypeArray> ids;
    ids->SetName(name);
    ids->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      ids->SetValue(i, i);
    }
    dsa->SetGlobalIds(ids);
  };
  add(data->GetPointData(), GlobalPointIdsName, data->GetNumberOfPoints());
  add(data->GetCellData(), GlobalCellIdsName, data->GetNumberOfCells());
}
