#include "vtkFEMorphMeshQuality.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "geometry/predicates.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
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

void AddValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

void AddCount(vtkFieldData* fd, const char* name, vtkIdType value)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

vtkSmartPointer<vtkDoubleArray> NewCellArray(const char* name, vtkIdType n)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  a->Fill(NaN);
  return a;
}

// The core's cell kind for a VTK cell type; false for cells not evaluated.
bool CellKindOf(int vtkType, femorph::CellKind& kind)
{
  switch (vtkType)
  {
    case VTK_PYRAMID: kind = femorph::CellKind::Pyramid; return true;
    case VTK_WEDGE: kind = femorph::CellKind::Wedge; return true;
    case VTK_HEXAHEDRON:
    case VTK_VOXEL: kind = femorph::CellKind::Hexahedron; return true;
    default: return false;
  }
}
}

//------------------------------------------------------------------------------
vtkFEMorphMeshQuality::vtkFEMorphMeshQuality() = default;
vtkFEMorphMeshQuality::~vtkFEMorphMeshQuality() = default;

//------------------------------------------------------------------------------
void vtkFEMorphMeshQuality::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "StretchThreshold: " << this->StretchThreshold << "\n";
}

//------------------------------------------------------------------------------
int vtkFEMorphMeshQuality::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphMeshQuality::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro("FEMorph Mesh Quality needs a vtkUnstructuredGrid input.");
    return 0;
  }

  const vtkIdType numCells = input->GetNumberOfCells();
  if (numCells == 0)
  {
    output->ShallowCopy(input);
    return 1;
  }
  // The clamp macro lets NaN through.
  if (!std::isfinite(this->StretchThreshold))
  {
    vtkErrorMacro("StretchThreshold must be a number in [0, 1]; it is "
      << this->StretchThreshold << ".");
    return 0;
  }

  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints > std::numeric_limits<femorph::index_t>::max())
  {
    vtkErrorMacro("FEMorph Mesh Quality handles up to "
      << std::numeric_limits<femorph::index_t>::max() << " points; the input has " << numPoints
      << ".");
    return 0;
  }
  if (const vtkIdType bad = vtkFEMorphMeshConversion::CountNonFinitePoints(input->GetPoints()))
  {
    vtkErrorMacro("FEMorph Mesh Quality: "
      << bad << (bad == 1 ? " point has" : " points have")
      << " NaN or infinite coordinates; no quality can be computed for the cells using them. "
         "Fix or remove these points first.");
    return 0;
  }

  std::vector<femorph::Vec3> points(static_cast<std::size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, points[i].data());
  }

  auto stretch = NewCellArray("Stretch", numCells);
  auto scaledJacobian = NewCellArray("ScaledJacobian", numCells);
  auto minDihedral = NewCellArray("MinDihedralAngle", numCells);
  auto maxDihedral = NewCellArray("MaxDihedralAngle", numCells);
  vtkNew<vtkUnsignedCharArray> inverted;
  inverted->SetName("Inverted");
  inverted->SetNumberOfTuples(numCells);
  inverted->Fill(0);

  Summary stretchSummary, jacobianSummary, minDihedralSummary, maxDihedralSummary;
  vtkIdType invertedCount = 0, invertedTets = 0, zeroVolumeCount = 0, belowThresholdCount = 0;
  vtkIdType tetraCount = 0, pyramidCount = 0, wedgeCount = 0, hexahedronCount = 0;
  std::array<vtkIdType, 256> skipped{};

  std::vector<femorph::Tet> chunkTets;
  std::vector<vtkIdType> chunkTetCells;
  std::vector<double> tetStretch, tetJacobian, tetMinDihedral, tetMaxDihedral;
  chunkTets.reserve(ChunkSize);
  chunkTetCells.reserve(ChunkSize);
  vtkNew<vtkIdList> cellPoints;
  // VTK_VOXEL's node order -> VTK_HEXAHEDRON's.
  constexpr int voxelToHex[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };

  try
  {
    for (vtkIdType begin = 0; begin < numCells; begin += ChunkSize)
    {
      const vtkIdType end = std::min(begin + ChunkSize, numCells);
      chunkTets.clear();
      chunkTetCells.clear();
      for (vtkIdType c = begin; c < end; ++c)
      {
        const int type = input->GetCellType(c);
        femorph::CellKind kind = femorph::CellKind::Tetra;
        const bool isTet = type == VTK_TETRA;
        if (!isTet && !CellKindOf(type, kind))
        {
          ++skipped[static_cast<unsigned char>(type)];
          continue;
        }
        input->GetCellPoints(c, cellPoints);
        const vtkIdType npts = cellPoints->GetNumberOfIds();
        const int expected = isTet ? 4 : femorph::cell_node_count(kind);
        if (npts != expected)
        {
          vtkErrorMacro("Cell " << c << " is a " << vtkFEMorphMeshConversion::CellTypeName(type)
                                << " with " << npts << " points instead of " << expected
                                << "; the input is corrupt.");
          return 0;
        }
        for (vtkIdType k = 0; k < npts; ++k)
        {
          const vtkIdType id = cellPoints->GetId(k);
          if (id < 0 || id >= numPoints)
          {
            vtkErrorMacro("Cell " << c << " refers to point " << id << " but the input has "
                                  << numPoints << " points; the input is corrupt.");
            return 0;
          }
        }

        if (isTet)
        {
          chunkTets.push_back({ { static_cast<femorph::index_t>(cellPoints->GetId(0)),
            static_cast<femorph::index_t>(cellPoints->GetId(1)),
            static_cast<femorph::index_t>(cellPoints->GetId(2)),
            static_cast<femorph::index_t>(cellPoints->GetId(3)) } });
          chunkTetCells.push_back(c);
          continue;
        }

        femorph::Vec3 corners[8];
        for (int k = 0; k < expected; ++k)
        {
          const int local = type == VTK_VOXEL ? voxelToHex[k] : k;
          corners[k] = points[cellPoints->GetId(local)];
        }
        double values[8];
        const int n = femorph::scaled_jacobian_corners(kind, corners, values);
        double minValue = std::numeric_limits<double>::infinity();
        for (int k = 0; k < n; ++k)
        {
          minValue = std::min(minValue, values[k]);
        }
        scaledJacobian->SetValue(c, minValue);
        jacobianSummary.Add(minValue);
        if (minValue < 0)
        {
          inverted->SetValue(c, 1);
          ++invertedCount;
        }
        switch (kind)
        {
          case femorph::CellKind::Pyramid: ++pyramidCount; break;
          case femorph::CellKind::Wedge: ++wedgeCount; break;
          default: ++hexahedronCount; break;
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
        stretchSummary.Add(tetStretch[i]);
        jacobianSummary.Add(tetJacobian[i]);
        minDihedralSummary.Add(minAngle);
        maxDihedralSummary.Add(maxAngle);
        // Exact sign: a float volume of a nearly flat tet may have either sign.
        const int sign =
          femorph::orient3d_sign(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
        if (sign < 0)
        {
          inverted->SetValue(c, 1);
          ++invertedCount;
          ++invertedTets;
        }
        else if (sign == 0)
        {
          ++zeroVolumeCount;
        }
        if (tetStretch[i] < this->StretchThreshold)
        {
          ++belowThresholdCount;
        }
      }
      tetraCount += static_cast<vtkIdType>(nt);

      this->UpdateProgress(static_cast<double>(end) / numCells);
      if (this->CheckAbort())
      {
        output->Initialize();
        return 1;
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("FEMorph Mesh Quality failed: " << e.what());
    return 0;
  }

  vtkIdType skippedCount = 0;
  for (vtkIdType n : skipped)
  {
    skippedCount += n;
  }
  if (skippedCount > 0)
  {
    vtkWarningMacro("FEMorph Mesh Quality evaluates tetrahedra, hexahedra, wedges and "
                    "pyramids only; "
      << vtkFEMorphMeshConversion::DescribeCellCounts(skipped)
      << (skippedCount == 1 ? " gets" : " get") << " NaN in the quality arrays.");
  }
  if (tetraCount > 0 && invertedTets == tetraCount)
  {
    vtkWarningMacro("All " << tetraCount
                           << " tetrahedra have negative volume: the mesh probably uses the "
                              "opposite vertex order to VTK_TETRA's (positive when "
                              "(p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0).");
  }

  output->ShallowCopy(input);
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(stretch);
  cd->AddArray(scaledJacobian);
  cd->AddArray(minDihedral);
  cd->AddArray(maxDihedral);
  cd->AddArray(inverted);
  cd->SetActiveScalars("Stretch");

  // After ShallowCopy the output owns its attribute and field data containers
  // (they share the input's arrays only), so adding arrays leaves the input
  // untouched (checked by TestMeshQuality).
  vtkFieldData* fd = output->GetFieldData();
  AddValue(fd, "StretchMin", stretchSummary.GetMin());
  AddValue(fd, "StretchMean", stretchSummary.GetMean());
  AddValue(fd, "StretchMax", stretchSummary.GetMax());
  AddValue(fd, "ScaledJacobianMin", jacobianSummary.GetMin());
  AddValue(fd, "ScaledJacobianMean", jacobianSummary.GetMean());
  AddValue(fd, "ScaledJacobianMax", jacobianSummary.GetMax());
  AddValue(fd, "MinDihedralAngleMin", minDihedralSummary.GetMin());
  AddValue(fd, "MinDihedralAngleMean", minDihedralSummary.GetMean());
  AddValue(fd, "MaxDihedralAngleMean", maxDihedralSummary.GetMean());
  AddValue(fd, "MaxDihedralAngleMax", maxDihedralSummary.GetMax());
  AddValue(fd, "StretchThreshold", this->StretchThreshold);
  AddCount(fd, "InvertedCount", invertedCount);
  AddCount(fd, "ZeroVolumeCount", zeroVolumeCount);
  AddCount(fd, "BelowThresholdCount", belowThresholdCount);
  AddCount(fd, "TetraCount", tetraCount);
  AddCount(fd, "PyramidCount", pyramidCount);
  AddCount(fd, "WedgeCount", wedgeCount);
  AddCount(fd, "HexahedronCount", hexahedronCount);
  AddCount(fd, "SkippedCellCount", skippedCount);
  return 1;
}
