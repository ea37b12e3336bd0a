// vtkFEMorphPieces: the pieces of a distributed grid merged into the serial
// mesh (ghost cells dropped, shared points merged by global id or by
// coordinates), empty pieces, Gather with one process, global ids on outputs.
#include "filters_test_utils.h"

#include "vtkFEMorphPieces.h"

#include "vtkDataSetAttributes.h"
#include "vtkDummyController.h"

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <vector>

namespace
{
using femorph_test::MakeGrid;
using femorph_test::ReadPart;

using Coords = std::array<double, 3>;
using CellKey = std::vector<Coords>;

// A cell by its points' coordinates, sorted: the same cell in any numbering.
CellKey KeyOf(vtkUnstructuredGrid* grid, vtkIdType cell)
{
  vtkNew<vtkIdList> ids;
  grid->GetCellPoints(cell, ids);
  CellKey key;
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
  {
    Coords x;
    grid->GetPoint(ids->GetId(k), x.data());
    key.push_back(x);
  }
  std::sort(key.begin(), key.end());
  return key;
}

void AddMarks(vtkUnstructuredGrid* grid)
{
  vtkNew<vtkDoubleArray> pointMark, cellMark;
  pointMark->SetName("PointMark");
  cellMark->SetName("CellMark");
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    pointMark->InsertNextValue(static_cast<double>(i));
  }
  for (vtkIdType i = 0; i < grid->GetNumberOfCells(); ++i)
  {
    cellMark->InsertNextValue(static_cast<double>(i));
  }
  grid->GetPointData()->AddArray(pointMark);
  grid->GetCellData()->AddArray(cellMark);
}

/**
 * The piece of `serial` holding the cells with owner[c] == piece, plus (with
 * `ghosts`) every other cell sharing a point with them, flagged
 * DUPLICATECELL. Local points in reverse order of first use, so the piece's
 * numbering is not the serial one; with `globalIds`, the serial ids as
 * global ids.
 */
vtkSmartPointer<vtkUnstructuredGrid> MakePiece(vtkUnstructuredGrid* serial,
  const std::vector<int>& owner, int piece, bool ghosts, bool globalIds)
{
  const vtkIdType numCells = serial->GetNumberOfCells();
  std::vector<char> owned(static_cast<std::size_t>(serial->GetNumberOfPoints()), 0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    if (owner[c] == piece)
    {
      serial->GetCellPoints(c, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        owned[ids->GetId(k)] = 1;
      }
    }
  }
  std::vector<vtkIdType> cells;
  std::vector<unsigned char> ghost;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    bool touches = false;
    serial->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      touches = touches || owned[ids->GetId(k)];
    }
    if (owner[c] == piece || (ghosts && touches))
    {
      cells.push_back(c);
      ghost.push_back(owner[c] == piece ? 0 : vtkDataSetAttributes::DUPLICATECELL);
    }
  }
  std::vector<vtkIdType> used;
  std::vector<vtkIdType> local(owned.size(), -1);
  for (vtkIdType c : cells)
  {
    serial->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      if (local[ids->GetId(k)] < 0)
      {
        local[ids->GetId(k)] = 0;
        used.push_back(ids->GetId(k));
      }
    }
  }
  std::reverse(used.begin(), used.end());
  std::vector<Coords> points;
  for (std::size_t i = 0; i < used.size(); ++i)
  {
    local[used[i]] = static_cast<vtkIdType>(i);
    Coords x;
    serial->GetPoint(used[i], x.data());
    points.push_back(x);
  }
  std::vector<std::pair<int, std::vector<vtkIdType>>> cellList;
  for (vtkIdType c : cells)
  {
    serial->GetCellPoints(c, ids);
    std::vector<vtkIdType> p;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      p.push_back(local[ids->GetId(k)]);
    }
    cellList.push_back({ serial->GetCellType(c), p });
  }
  auto grid = MakeGrid(points, cellList);
  auto copy = [](vtkDataArray* from, const std::vector<vtkIdType>& rows, const char* name) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    for (vtkIdType r : rows)
    {
      a->InsertNextValue(from->GetComponent(r, 0));
    }
    return vtkSmartPointer<vtkDoubleArray>(a);
  };
  grid->GetPointData()->AddArray(copy(serial->GetPointData()->GetArray("PointMark"), used, "PointMark"));
  grid->GetCellData()->AddArray(copy(serial->GetCellData()->GetArray("CellMark"), cells, "CellMark"));
  if (ghosts)
  {
    vtkNew<vtkUnsignedCharArray> g;
    g->SetName(vtkDataSetAttributes::GhostArrayName());
    for (unsigned char v : ghost)
    {
      g->InsertNextValue(v);
    }
    grid->GetCellData()->AddArray(g);
  }
  if (globalIds)
  {
    vtkNew<vtkIdTypeArray> gp, gc;
    gp->SetName("vtkGlobalPointIds");
    gc->SetName("vtkGlobalCellIds");
    for (vtkIdType p : used)
    {
      gp->InsertNextValue(p);
    }
    for (vtkIdType c : cells)
    {
      gc->InsertNextValue(c);
    }
    grid->GetPointData()->SetGlobalIds(gp);
    grid->GetCellData()->SetGlobalIds(gc);
  }
  return grid;
}

// Interleaved owners: every piece touches every other along many faces.
std::vector<int> Owners(vtkIdType numCells)
{
  std::vector<int> owner(static_cast<std::size_t>(numCells));
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    owner[c] = static_cast<int>((c / 7) % 2);
  }
  return owner;
}

// The merged grid holds the serial mesh's cells, each once, with the point
// and cell data of the serial point and cell at the same place.
void ExpectSameMesh(vtkUnstructuredGrid* serial, vtkUnstructuredGrid* merged)
{
  ASSERT_EQ(merged->GetNumberOfCells(), serial->GetNumberOfCells());
  ASSERT_EQ(merged->GetNumberOfPoints(), serial->GetNumberOfPoints());
  std::map<CellKey, vtkIdType> serialCells;
  for (vtkIdType c = 0; c < serial->GetNumberOfCells(); ++c)
  {
    serialCells[KeyOf(serial, c)] = c;
  }
  std::map<Coords, vtkIdType> serialPoints;
  for (vtkIdType p = 0; p < serial->GetNumberOfPoints(); ++p)
  {
    Coords x;
    serial->GetPoint(p, x.data());
    serialPoints[x] = p;
  }
  vtkDataArray* cellMark = merged->GetCellData()->GetArray("CellMark");
  vtkDataArray* pointMark = merged->GetPointData()->GetArray("PointMark");
  ASSERT_NE(cellMark, nullptr);
  ASSERT_NE(pointMark, nullptr);
  std::vector<char> seen(static_cast<std::size_t>(serial->GetNumberOfCells()), 0);
  for (vtkIdType c = 0; c < merged->GetNumberOfCells(); ++c)
  {
    auto it = serialCells.find(KeyOf(merged, c));
    ASSERT_NE(it, serialCells.end()) << "merged cell " << c << " is not a serial cell";
    EXPECT_FALSE(seen[it->second]) << "serial cell " << it->second << " twice";
    seen[it->second] = 1;
    EXPECT_EQ(cellMark->GetComponent(c, 0), static_cast<double>(it->second));
  }
  for (vtkIdType p = 0; p < merged->GetNumberOfPoints(); ++p)
  {
    Coords x;
    merged->GetPoint(p, x.data());
    ASSERT_EQ(serialPoints.count(x), 1u);
    EXPECT_EQ(pointMark->GetComponent(p, 0), static_cast<double>(serialPoints[x]));
  }
  EXPECT_EQ(merged->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()), nullptr);
  EXPECT_EQ(merged->GetPointData()->GetArray("vtkGlobalPointIds"), nullptr);
  EXPECT_EQ(merged->GetCellData()->GetArray("vtkGlobalCellIds"), nullptr);
}

vtkSmartPointer<vtkUnstructuredGrid> Beam()
{
  auto grid = ReadPart("beam.vtu");
  if (grid)
  {
    AddMarks(grid);
  }
  return grid;
}
}

//------------------------------------------------------------------------------
TEST(Pieces, TwoPiecesSharingPointsMergeByCoordinatesIntoTheSerialMesh)
{
  auto serial = Beam();
  ASSERT_TRUE(serial) << "Data/beam.vtu is missing";
  const auto owner = Owners(serial->GetNumberOfCells());
  auto a = MakePiece(serial, owner, 0, false, false);
  auto b = MakePiece(serial, owner, 1, false, false);
  // Shared points are really in both pieces.
  ASSERT_GT(a->GetNumberOfPoints() + b->GetNumberOfPoints(), serial->GetNumberOfPoints() + 100);
  ExpectSameMesh(serial, vtkFEMorphPieces::MergePieces({ a, b }));
}

TEST(Pieces, GhostCellsAreDroppedBeforeMerging)
{
  auto serial = Beam();
  ASSERT_TRUE(serial);
  const auto owner = Owners(serial->GetNumberOfCells());
  auto a = MakePiece(serial, owner, 0, true, false);
  auto b = MakePiece(serial, owner, 1, true, false);
  ASSERT_GT(a->GetNumberOfCells() + b->GetNumberOfCells(), serial->GetNumberOfCells() + 100);
  ExpectSameMesh(serial, vtkFEMorphPieces::MergePieces({ a, b }));
  // One piece alone without its ghosts: exactly its own cells.
  auto own = vtkFEMorphPieces::DropGhostCells(a);
  EXPECT_EQ(own->GetNumberOfCells(), static_cast<vtkIdType>(std::count(owner.begin(), owner.end(), 0)));
}

TEST(Pieces, GlobalIdsGiveTheSerialOrderExactly)
{
  auto serial = Beam();
  ASSERT_TRUE(serial);
  const auto owner = Owners(serial->GetNumberOfCells());
  // The pieces in reverse order, with ghosts: the ids alone restore the order.
  auto merged = vtkFEMorphPieces::MergePieces({ MakePiece(serial, owner, 1, true, true),
    MakePiece(serial, owner, 0, true, true) });
  ExpectSameMesh(serial, merged);
  ASSERT_EQ(merged->GetNumberOfPoints(), serial->GetNumberOfPoints());
  for (vtkIdType p = 0; p < serial->GetNumberOfPoints(); ++p)
  {
    Coords x, y;
    serial->GetPoint(p, x.data());
    merged->GetPoint(p, y.data());
    ASSERT_EQ(x, y) << "point " << p;
  }
  vtkNew<vtkIdList> s, m;
  for (vtkIdType c = 0; c < serial->GetNumberOfCells(); ++c)
  {
    serial->GetCellPoints(c, s);
    merged->GetCellPoints(c, m);
    ASSERT_EQ(s->GetNumberOfIds(), m->GetNumberOfIds());
    for (vtkIdType k = 0; k < s->GetNumberOfIds(); ++k)
    {
      ASSERT_EQ(s->GetId(k), m->GetId(k)) << "cell " << c;
    }
  }
}

TEST(Pieces, EmptyAndMissingPiecesAreIgnored)
{
  auto serial = Beam();
  ASSERT_TRUE(serial);
  std::vector<int> owner(static_cast<std::size_t>(serial->GetNumberOfCells()), 0);
  auto whole = MakePiece(serial, owner, 0, false, false);
  vtkNew<vtkUnstructuredGrid> empty;
  ExpectSameMesh(serial, vtkFEMorphPieces::MergePieces({ empty, whole, nullptr }));
  auto none = vtkFEMorphPieces::MergePieces({ empty, nullptr });
  EXPECT_EQ(none->GetNumberOfCells(), 0);
  EXPECT_EQ(none->GetNumberOfPoints(), 0);
  // A piece of ghost cells only adds nothing.
  std::vector<int> split = Owners(serial->GetNumberOfCells());
  auto ghostsOnly = MakePiece(serial, split, 0, true, false);
  vtkUnsignedCharArray* g = ghostsOnly->GetCellGhostArray();
  ASSERT_NE(g, nullptr);
  g->Fill(vtkDataSetAttributes::DUPLICATECELL);
  ExpectSameMesh(serial, vtkFEMorphPieces::MergePieces({ ghostsOnly, whole }));
}

TEST(Pieces, CoincidentPointsOfOnePieceStayDistinct)
{
  // Two tets touching along a seam of duplicate points (an unmerged mesh):
  // merging pieces must not merge the seam, which Segment reports.
  auto seam = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 0 },
                         { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 7, 4, 6, 5 } } });
  auto merged = vtkFEMorphPieces::MergePieces({ seam });
  EXPECT_EQ(merged->GetNumberOfPoints(), 8);
  // Split over two pieces, each with the seam's two sides' copies once:
  // each side's copy matches the other piece's first copy there.
  auto left = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } } });
  auto right = MakeGrid({ { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 3, 0, 2, 1 } } });
  EXPECT_EQ(vtkFEMorphPieces::MergePieces({ left, right })->GetNumberOfPoints(), 5);
}

TEST(Pieces, GatherWithOneProcessDropsGhostsAndGlobalIdsAreAdded)
{
  auto serial = Beam();
  ASSERT_TRUE(serial);
  const auto owner = Owners(serial->GetNumberOfCells());
  auto a = MakePiece(serial, owner, 0, true, false);
  vtkNew<vtkDummyController> controller;
  auto gathered = vtkFEMorphPieces::Gather(controller, a);
  ASSERT_TRUE(gathered);
  EXPECT_EQ(gathered->GetNumberOfCells(), static_cast<vtkIdType>(std::count(owner.begin(), owner.end(), 0)));
  EXPECT_EQ(gathered->GetCellGhostArray(), nullptr);
  EXPECT_TRUE(vtkFEMorphPieces::Gather(controller, nullptr));

  vtkFEMorphPieces::AddGlobalIds(gathered);
  vtkDataArray* gp = gathered->GetPointData()->GetGlobalIds();
  vtkDataArray* gc = gathered->GetCellData()->GetGlobalIds();
  ASSERT_NE(gp, nullptr);
  ASSERT_NE(gc, nullptr);
  EXPECT_STREQ(gp->GetName(), "vtkGlobalPointIds");
  EXPECT_STREQ(gc->GetName(), "vtkGlobalCellIds");
  ASSERT_EQ(gp->GetNumberOfTuples(), gathered->GetNumberOfPoints());
  for (vtkIdType i = 0; i < gp->GetNumberOfTuples(); ++i)
  {
    ASSERT_EQ(gp->GetComponent(i, 0), static_cast<double>(i));
  }
  // Existing ids are kept.
  gc->SetComponent(0, 0, 41);
  vtkFEMorphPieces::AddGlobalIds(gathered);
  EXPECT_EQ(gathered->GetCellData()->GetGlobalIds()->GetComponent(0, 0), 41);
}
