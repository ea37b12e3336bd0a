#include "vtkFEMorphMeshQuality.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "geometry/predicates.h"
#include "quality/is_valid_cell.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkFEMorphMeshQuality);

namespace
{
// Cells between two progress updates and abort checks: small enough to react
// within a fraction of a second, large enough for the core's parallel loop.
constexpr vtkIdType ChunkSize = 1 << 15;
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

// Min / mean / max of a measure over the cells that have it.
struct Summary
{
  double Min = std::numeric_limits<double>::infinity();
  double Max = -std::numeric_limits<double>::infinity();
  double Sum = 0;
  vtkIdType Count = 0;

  void Add(double v)
  {
    this->Min = std::min(this->Min, v);
    this->Max = std::max(this->Max, v);
    this->Sum += v;
    ++this->Count;
  }
  double GetMin() const { return this->Count ? this->Min : NaN; }
  double GetMax() const { return this->Count ? this->Max : NaN; }
  double GetMean() const { return this->Count ? this->Sum / this->Count : NaN; }
};

// The summaries and counts of one piece or of the whole mesh.
constexpr std::size_t PackedSummaryValues = 4 * 4; // 4 summaries of 4 values
enum Count
{
  InvertedCount,
  ZeroVolumeCount,
  InvalidCount,
  BelowThresholdCount,
  TetraCount,
  PyramidCount,
  WedgeCount,
  HexahedronCount,
  SkippedCellCount,
  NumCounts
};
struct Totals
{
  Summary Stretch, Jacobian, MinDihedral, MaxDihedral;
  std::array<vtkIdType, NumCounts> Counts{};

  std::array<Summary*, 4> Summaries() { return { &Stretch, &Jacobian, &MinDihedral, &MaxDihedral }; }

  // Flattened: min, max, sum, count of each summary, then the counts.
  std::vector<double> Pack()
  {
    std::vector<double> v;
    for (Summary* s : this->Summaries())
    {
      v.insert(v.end(), { s->Min, s->Max, s->Sum, static_cast<double>(s->Count) });
    }
    for (vtkIdType c : this->Counts)
    {
      v.push_back(static_cast<double>(c));
    }
    return v;
  }
  void Unpack(const std::vector<double>& v)
  {
    std::size_t i = 0;
    for (Summary* s : this->Summaries())
    {
      s->Min = v[i++];
      s->Max = v[i++];
      s->Sum = v[i++];
      s->Count = static_cast<vtkIdType>(v[i++]);
    }
    for (vtkIdType& c : this->Counts)
    {
      c = static_cast<vtkIdType>(v[i++]);
    }
  }
};

void WriteTotals(vtkFieldData* fd, const Totals& t, double threshold)
{
  using A = vtkFEMorphAlgorithm;
  A::AddValue(fd, "StretchMin", t.Stretch.GetMin());
  A::AddValue(fd, "StretchMean", t.Stretch.GetMean());
  A::AddValue(fd, "StretchMax", t.Stretch.GetMax());
  A::AddValue(fd, "ScaledJacobianMin", t.Jacobian.GetMin());
  A::AddValue(fd, "ScaledJacobianMean", t.Jacobian.GetMean());
  A::AddValue(fd, "ScaledJacobianMax", t.Jacobian.GetMax());
  A::AddValue(fd, "MinDihedralAngleMin", t.MinDihedral.GetMin());
  A::AddValue(fd, "MinDihedralAngleMean", t.MinDihedral.GetMean());
  A::AddValue(fd, "MaxDihedralAngleMean", t.MaxDihedral.GetMean());
  A::AddValue(fd, "MaxDihedralAngleMax", t.MaxDihedral.GetMax());
  A::AddValue(fd, "StretchThreshold", threshold);
  A::AddCount(fd, "InvertedCount", t.Counts[InvertedCount]);
  A::AddCount(fd, "ZeroVolumeCount", t.Counts[ZeroVolumeCount]);
  A::AddCount(fd, "InvalidCount", t.Counts[InvalidCount]);
  A::AddCount(fd, "BelowThresholdCount", t.Counts[BelowThresholdCount]);
  A::AddCount(fd, "TetraCount", t.Counts[TetraCount]);
  A::AddCount(fd, "PyramidCount", t.Counts[PyramidCount]);
  A::AddCount(fd, "WedgeCount", t.Counts[WedgeCount]);
  A::AddCount(fd, "HexahedronCount", t.Counts[HexahedronCount]);
  A::AddCount(fd, "SkippedCellCount", t.Counts[SkippedCellCount]);
}

vtkSmartPointer<vtkDoubleArray> NewCellArray(const char* name, vtkIdType n)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  a->Fill(NaN);
  return a;
}
}

//------------------------------------------------------------------------------
vtkFEMorphMeshQuality::vtkFEMorphMeshQuality()
  : vtkFEMorphAlgorithm("FEMorph Mesh Quality", AnyCells)
{
}

vtkFEMorphMeshQuality::~vtkFEMorphMeshQuality() = default;

//------------------------------------------------------------------------------
void vtkFEMorphMeshQuality::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "StretchThreshold: " << this->StretchThreshold << "\n";
}

//------------------------------------------------------------------------------
bool vtkFEMorphMeshQuality::CheckProperties()
{
  return this->CheckRange("StretchThreshold", this->StretchThreshold, 0, 1);
}

//------------------------------------------------------------------------------
bool vtkFEMorphMeshQuality::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  const vtkIdType numCells = input->GetNumberOfCells();
  const std::vector<femorph::Vec3> points = vtkFEMorphMeshConversion::ReadPoints(input);
  femorph::MixedCells cells;
  std::vector<vtkIdType> cellIds;
  std::array<vtkIdType, 256> skipped{};
  vtkFEMorphMeshConversion::ReadLinearCells(input, cells, &cellIds, &skipped);

  auto stretch = NewCellArray("Stretch", numCells);
  auto scaledJacobian = NewCellArray("ScaledJacobian", numCells);
  auto minDihedral = NewCellArray("MinDihedralAngle", numCells);
  auto maxDihedral = NewCellArray("MaxDihedralAngle", numCells);
  vtkNew<vtkUnsignedCharArray> inverted;
  inverted->SetName("Inverted");
  inverted->SetNumberOfTuples(numCells);
  inverted->Fill(0);
  // FEMorph's one definition of a valid cell (Core/quality/is_valid_cell.h),
  // the one Hex To Tet's inverted tets follow: stricter than the scaled
  // Jacobian's corners (a hexahedron with its top face turned by
  // 90 degrees has ScaledJacobian 0.707 and is Invalid).
  vtkNew<vtkUnsignedCharArray> invalid;
  invalid->SetName("Invalid");
  invalid->SetNumberOfTuples(numCells);
  invalid->Fill(0);

  // Ghost cells (another piece's own, under MPI) get their values but stay
  // out of the counts and summaries: each cell is counted by one piece.
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  auto isGhost = [ghosts](vtkIdType c) {
    return ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL) != 0;
  };
  Totals totals;
  Summary& stretchSummary = totals.Stretch;
  Summary& jacobianSummary = totals.Jacobian;
  Summary& minDihedralSummary = totals.MinDihedral;
  Summary& maxDihedralSummary = totals.MaxDihedral;
  vtkIdType invertedCount = 0, invertedTets = 0, zeroVolumeCount = 0, belowThresholdCount = 0,
            invalidCount = 0, ghostTets = 0;
  std::array<vtkIdType, 4> kindCounts{};

  std::vector<femorph::Tet> chunkTets;
  std::vector<vtkIdType> chunkTetCells;
  std::vector<double> tetStretch, tetJacobian, tetMinDihedral, tetMaxDihedral;
  chunkTets.reserve(ChunkSize);
  chunkTetCells.reserve(ChunkSize);
  const vtkIdType numRead = cells.size();
  for (vtkIdType begin = 0; begin < numRead; begin += ChunkSize)
  {
    const vtkIdType end = std::min(begin + ChunkSize, numRead);
    chunkTets.clear();
    chunkTetCells.clear();
    for (vtkIdType i = begin; i < end; ++i)
    {
      const femorph::CellKind kind = cells.kinds[i];
      const femorph::index_t* nodes = cells.nodes(static_cast<femorph::index_t>(i));
      const vtkIdType c = cellIds[i];
      const bool ghost = isGhost(c);
      kindCounts[static_cast<int>(kind)] += ghost ? 0 : 1;
      if (kind == femorph::CellKind::Tetra)
      {
        ghostTets += ghost ? 1 : 0;
        chunkTets.push_back({ { nodes[0], nodes[1], nodes[2], nodes[3] } });
        chunkTetCells.push_back(c);
        continue;
      }
      femorph::Vec3 corners[8];
      const int n = femorph::cell_node_count(kind);
      for (int k = 0; k < n; ++k)
      {
        corners[k] = points[nodes[k]];
      }
      const double minValue = femorph::min_scaled_jacobian(kind, corners);
      scaledJacobian->SetValue(c, minValue);
      const vtkIdType counted = ghost ? 0 : 1;
      if (!ghost)
      {
        jacobianSummary.Add(minValue);
      }
      if (minValue < 0)
      {
        inverted->SetValue(c, 1);
        invertedCount += counted;
      }
      if (!femorph::is_valid_cell(kind, corners))
      {
        invalid->SetValue(c, 1);
        invalidCount += counted;
      }
    }

    // The tets of this chunk in one parallel pass of the core.
    const std::size_t nt = chunkTets.size();
    tetStretch.resize(nt);
    tetJacobian.resize(nt);
    tetMinDihedral.resize(nt);
    tetMaxDihedral.resize(nt);
    if (nt > 0)
    {
      femorph::compute_tet_quality(points, chunkTets, tetStretch.data(), tetJacobian.data(),
        tetMinDihedral.data(), tetMaxDihedral.data(), nullptr);
    }
    for (std::size_t i = 0; i < nt; ++i)
    {
      const vtkIdType c = chunkTetCells[i];
      const femorph::Tet& t = chunkTets[i];
      const double minAngle = vtkMath::DegreesFromRadians(tetMinDihedral[i]);
      const double maxAngle = vtkMath::DegreesFromRadians(tetMaxDihedral[i]);
      stretch->SetValue(c, tetStretch[i]);
      scaledJacobian->SetValue(c, tetJacobian[i]);
      minDihedral->SetValue(c, minAngle);
      maxDihedral->SetValue(c, maxAngle);
      const bool ghost = isGhost(c);
      const vtkIdType counted = ghost ? 0 : 1;
      if (!ghost)
      {
        stretchSummary.Add(tetStretch[i]);
        jacobianSummary.Add(tetJacobian[i]);
        minDihedralSummary.Add(minAngle);
        maxDihedralSummary.Add(maxAngle);
      }
      // Exact sign: a float volume of a nearly flat tet may have either sign.
      const int sign =
        femorph::orient3d_sign(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
      if (sign <= 0)
      {
        invalid->SetValue(c, 1);
        invalidCount += counted;
      }
      if (sign < 0)
      {
        inverted->SetValue(c, 1);
        invertedCount += counted;
        ++invertedTets;
      }
      else if (sign == 0)
      {
        zeroVolumeCount += counted;
      }
      if (tetStretch[i] < this->StretchThreshold)
      {
        belowThresholdCount += counted;
      }
    }
    if (!this->Progress(static_cast<double>(end) / numRead))
    {
      return true;
    }
  }

  vtkIdType skippedCount = 0;
  for (vtkIdType n : skipped)
  {
    skippedCount += n;
  }
  // Skipped ghost cells: the ghosts among all cells but not among those read.
  vtkIdType skippedGhosts = 0;
  for (vtkIdType c = 0; ghosts && c < numCells; ++c)
  {
    skippedGhosts += isGhost(c) ? 1 : 0;
  }
  for (vtkIdType i = 0; ghosts && i < numRead; ++i)
  {
    skippedGhosts -= isGhost(cellIds[i]) ? 1 : 0;
  }
  if (skippedCount > 0)
  {
    this->Warn("tetrahedra, hexahedra, wedges and pyramids are evaluated, nothing else; " +
      vtkFEMorphMeshConversion::DescribeCellCounts(skipped) +
      (skippedCount == 1 ? " gets" : " get") + " NaN in the quality arrays.");
  }
  const vtkIdType tetraCount = kindCounts[static_cast<int>(femorph::CellKind::Tetra)];
  if (tetraCount > 0 && invertedTets == tetraCount + ghostTets)
  {
    this->Warn("all " + std::to_string(tetraCount) +
      " tetrahedra have negative volume: the mesh probably uses the opposite vertex order to "
      "VTK_TETRA's (positive when (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0).");
  }

  output->ShallowCopy(input);
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(stretch);
  cd->AddArray(scaledJacobian);
  cd->AddArray(minDihedral);
  cd->AddArray(maxDihedral);
  cd->AddArray(inverted);
  cd->AddArray(invalid);
  cd->SetActiveScalars("Stretch");

  // After ShallowCopy the output owns its attribute and field data containers
  // (they share the input's arrays only), so adding arrays leaves the input
  // untouched (checked by TestMeshQuality).
  vtkFieldData* fd = output->GetFieldData();
  totals.Counts[InvertedCount] = invertedCount;
  totals.Counts[ZeroVolumeCount] = zeroVolumeCount;
  totals.Counts[InvalidCount] = invalidCount;
  totals.Counts[BelowThresholdCount] = belowThresholdCount;
  totals.Counts[TetraCount] = tetraCount;
  totals.Counts[PyramidCount] = kindCounts[static_cast<int>(femorph::CellKind::Pyramid)];
  totals.Counts[WedgeCount] = kindCounts[static_cast<int>(femorph::CellKind::Wedge)];
  totals.Counts[HexahedronCount] = kindCounts[static_cast<int>(femorph::CellKind::Hexahedron)];
  totals.Counts[SkippedCellCount] = skippedCount - skippedGhosts;
  WriteTotals(fd, totals, this->StretchThreshold);
  this->PieceTotals = totals.Pack();
  return true;
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshQuality::CombinePieces(
  vtkMultiProcessController* controller, vtkInformationVector* outputVector)
{
  // Every piece ran Execute() (an empty one too), so PieceTotals has the
  // same layout everywhere: min, max, sum, count per summary, then counts.
  const std::vector<double> local = this->PieceTotals;
  const std::size_t n = local.size();
  std::vector<double> mins(n), maxs(n), sums(n);
  controller->AllReduce(local.data(), mins.data(), static_cast<vtkIdType>(n), vtkCommunicator::MIN_OP);
  controller->AllReduce(local.data(), maxs.data(), static_cast<vtkIdType>(n), vtkCommunicator::MAX_OP);
  controller->AllReduce(local.data(), sums.data(), static_cast<vtkIdType>(n), vtkCommunicator::SUM_OP);
  std::vector<double> global = sums;
  for (std::size_t s = 0; s < PackedSummaryValues && s + 4 <= n; s += 4)
  {
    global[s] = mins[s];
    global[s + 1] = maxs[s + 1];
  }
  Totals totals;
  totals.Unpack(global);
  if (vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0))
  {
    WriteTotals(output->GetFieldData(), totals, this->StretchThreshold);
  }
}
