#include "vtkFEMorphMeshConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <cmath>
#include <limits>
#include <sstream>

namespace
{
// The core numbers vertices and tets with 32-bit ids.
constexpr vtkIdType MaxCoreIndex = std::numeric_limits<femorph::index_t>::max();
}

//------------------------------------------------------------------------------
std::string vtkFEMorphMeshConversion::CellTypeName(int cellType)
{
  switch (cellType)
  {
    case VTK_EMPTY_CELL: return "VTK_EMPTY_CELL";
    case VTK_VERTEX: return "VTK_VERTEX";
    case VTK_POLY_VERTEX: return "VTK_POLY_VERTEX";
    case VTK_LINE: return "VTK_LINE";
    case VTK_POLY_LINE: return "VTK_POLY_LINE";
    case VTK_TRIANGLE: return "VTK_TRIANGLE";
    case VTK_TRIANGLE_STRIP: return "VTK_TRIANGLE_STRIP";
    case VTK_POLYGON: return "VTK_POLYGON";
    case VTK_PIXEL: return "VTK_PIXEL";
    case VTK_QUAD: return "VTK_QUAD";
    case VTK_TETRA: return "VTK_TETRA";
    case VTK_VOXEL: return "VTK_VOXEL";
    case VTK_HEXAHEDRON: return "VTK_HEXAHEDRON";
    case VTK_WEDGE: return "VTK_WEDGE";
    case VTK_PYRAMID: return "VTK_PYRAMID";
    case VTK_PENTAGONAL_PRISM: return "VTK_PENTAGONAL_PRISM";
    case VTK_HEXAGONAL_PRISM: return "VTK_HEXAGONAL_PRISM";
    case VTK_QUADRATIC_EDGE: return "VTK_QUADRATIC_EDGE";
    case VTK_QUADRATIC_TRIANGLE: return "VTK_QUADRATIC_TRIANGLE";
    case VTK_QUADRATIC_QUAD: return "VTK_QUADRATIC_QUAD";
    case VTK_QUADRATIC_POLYGON: return "VTK_QUADRATIC_POLYGON";
    case VTK_QUADRATIC_TETRA: return "VTK_QUADRATIC_TETRA";
    case VTK_QUADRATIC_HEXAHEDRON: return "VTK_QUADRATIC_HEXAHEDRON";
    case VTK_QUADRATIC_WEDGE: return "VTK_QUADRATIC_WEDGE";
    case VTK_QUADRATIC_PYRAMID: return "VTK_QUADRATIC_PYRAMID";
    case VTK_BIQUADRATIC_QUAD: return "VTK_BIQUADRATIC_QUAD";
    case VTK_TRIQUADRATIC_HEXAHEDRON: return "VTK_TRIQUADRATIC_HEXAHEDRON";
    case VTK_TRIQUADRATIC_PYRAMID: return "VTK_TRIQUADRATIC_PYRAMID";
    case VTK_QUADRATIC_LINEAR_QUAD: return "VTK_QUADRATIC_LINEAR_QUAD";
    case VTK_QUADRATIC_LINEAR_WEDGE: return "VTK_QUADRATIC_LINEAR_WEDGE";
    case VTK_BIQUADRATIC_QUADRATIC_WEDGE: return "VTK_BIQUADRATIC_QUADRATIC_WEDGE";
    case VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON: return "VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON";
    case VTK_BIQUADRATIC_TRIANGLE: return "VTK_BIQUADRATIC_TRIANGLE";
    case VTK_CUBIC_LINE: return "VTK_CUBIC_LINE";
    case VTK_CONVEX_POINT_SET: return "VTK_CONVEX_POINT_SET";
    case VTK_POLYHEDRON: return "VTK_POLYHEDRON";
    case VTK_LAGRANGE_CURVE: return "VTK_LAGRANGE_CURVE";
    case VTK_LAGRANGE_TRIANGLE: return "VTK_LAGRANGE_TRIANGLE";
    case VTK_LAGRANGE_QUADRILATERAL: return "VTK_LAGRANGE_QUADRILATERAL";
    case VTK_LAGRANGE_TETRAHEDRON: return "VTK_LAGRANGE_TETRAHEDRON";
    case VTK_LAGRANGE_HEXAHEDRON: return "VTK_LAGRANGE_HEXAHEDRON";
    case VTK_LAGRANGE_WEDGE: return "VTK_LAGRANGE_WEDGE";
    case VTK_LAGRANGE_PYRAMID: return "VTK_LAGRANGE_PYRAMID";
    case VTK_BEZIER_CURVE: return "VTK_BEZIER_CURVE";
    case VTK_BEZIER_TRIANGLE: return "VTK_BEZIER_TRIANGLE";
    case VTK_BEZIER_QUADRILATERAL: return "VTK_BEZIER_QUADRILATERAL";
    case VTK_BEZIER_TETRAHEDRON: return "VTK_BEZIER_TETRAHEDRON";
    case VTK_BEZIER_HEXAHEDRON: return "VTK_BEZIER_HEXAHEDRON";
    case VTK_BEZIER_WEDGE: return "VTK_BEZIER_WEDGE";
    case VTK_BEZIER_PYRAMID: return "VTK_BEZIER_PYRAMID";
    default: break;
  }
  return "cell type " + std::to_string(cellType);
}

//------------------------------------------------------------------------------
vtkIdType vtkFEMorphMeshConversion::DescribeOtherCells(
  vtkUnstructuredGrid* input, int acceptedType, std::string& description)
{
  description.clear();
  std::array<vtkIdType, 256> counts{};
  const vtkIdType numCells = input->GetNumberOfCells();
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    ++counts[static_cast<unsigned char>(input->GetCellType(c))];
  }
  counts[static_cast<unsigned char>(acceptedType)] = 0;
  description = DescribeCellCounts(counts);
  vtkIdType total = 0;
  for (vtkIdType n : counts)
  {
    total += n;
  }
  return total;
}

//------------------------------------------------------------------------------
std::string vtkFEMorphMeshConversion::DescribeCellCounts(const std::array<vtkIdType, 256>& counts)
{
  std::vector<std::string> parts;
  vtkIdType total = 0;
  for (int type = 0; type < 256; ++type)
  {
    if (counts[type] > 0)
    {
      parts.push_back(std::to_string(counts[type]) + " " + CellTypeName(type));
      total += counts[type];
    }
  }
  std::string description;
  for (std::size_t i = 0; i < parts.size(); ++i)
  {
    if (i > 0)
    {
      description += (i + 1 == parts.size()) ? " and " : ", ";
    }
    description += parts[i];
  }
  if (total > 0)
  {
    description += total == 1 ? " cell" : " cells";
  }
  return description;
}

//------------------------------------------------------------------------------
vtkIdType vtkFEMorphMeshConversion::CountNonFinitePoints(vtkPoints* points)
{
  if (!points)
  {
    return 0;
  }
  vtkIdType count = 0;
  const vtkIdType numPoints = points->GetNumberOfPoints();
  double p[3];
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    points->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      ++count;
    }
  }
  return count;
}

//------------------------------------------------------------------------------
femorph::Status vtkFEMorphMeshConversion::ToTetMesh(vtkUnstructuredGrid* input,
  const std::string& filterLabel, femorph::BuildOptions options, femorph::TetMesh& mesh,
  femorph::BuildReport* report, std::vector<std::string>* warnings)
{
  mesh = femorph::TetMesh();
  auto fail = [&](const std::string& what) {
    return femorph::Status::failure(filterLabel + ": " + what);
  };
  auto warn = [&](const std::string& what) {
    if (warnings)
    {
      warnings->push_back(filterLabel + ": " + what);
    }
  };

  if (!input || input->GetNumberOfCells() == 0 || !input->GetPoints())
  {
    return fail("the input has no cells.");
  }
  std::string others;
  if (DescribeOtherCells(input, VTK_TETRA, others) > 0)
  {
    return femorph::Status::failure(filterLabel + " accepts tetrahedra only; the input has " +
      others + " (ParaView's Tetrahedralize filter converts them).");
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  const vtkIdType numCells = input->GetNumberOfCells();
  if (numPoints > MaxCoreIndex || numCells > MaxCoreIndex / 4)
  {
    return fail("the input is too large (" + std::to_string(numPoints) + " points, " +
      std::to_string(numCells) + " cells; the limit is " + std::to_string(MaxCoreIndex / 4) +
      " tetrahedra).");
  }
  if (const vtkIdType bad = CountNonFinitePoints(input->GetPoints()))
  {
    return fail(std::to_string(bad) + (bad == 1 ? " point has" : " points have") +
      " NaN or infinite coordinates.");
  }

  std::vector<femorph::Vec3> points(static_cast<std::size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, points[i].data());
  }
  std::vector<femorph::Tet> tets(static_cast<std::size_t>(numCells));
  // The cell array's own storage (no id list per cell: 30 ms at 0.5M tets).
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    input->GetCellPoints(c, npts, pts);
    if (npts != 4)
    {
      return fail("cell " + std::to_string(c) + " is a VTK_TETRA with " + std::to_string(npts) +
        " points instead of 4.");
    }
    for (int k = 0; k < 4; ++k)
    {
      tets[c][k] = static_cast<femorph::index_t>(pts[k]);
    }
  }

  options.face_regions.clear();
  if (vtkDataArray* regions = input->GetCellData()->GetArray(FaceRegionName))
  {
    if (regions->GetNumberOfComponents() != 4)
    {
      warn(std::string("the cell array ") + FaceRegionName + " has " +
        std::to_string(regions->GetNumberOfComponents()) +
        " components instead of 4 (one region per tet face); it is ignored.");
    }
    else
    {
      options.face_regions.resize(static_cast<std::size_t>(numCells));
      // FEMorph Segment writes ints: read them in place (GetComponent, per
      // value, took 15-30 ms at 0.5M tets).
      vtkIntArray* ints = vtkIntArray::FastDownCast(regions);
      const int* values = ints ? ints->GetPointer(0) : nullptr;
      for (vtkIdType c = 0; c < numCells; ++c)
      {
        for (int f = 0; f < 4; ++f)
        {
          options.face_regions[c][f] = values
            ? static_cast<femorph::index_t>(values[4 * c + f])
            : static_cast<femorph::index_t>(std::lround(regions->GetComponent(c, f)));
        }
      }
    }
  }

  femorph::BuildReport localReport;
  femorph::BuildReport& buildReport = report ? *report : localReport;
  femorph::Status status;
  try
  {
    status = mesh.build(std::move(points), std::move(tets), options, &buildReport);
  }
  catch (const std::exception& e)
  {
    mesh = femorph::TetMesh();
    return fail(std::string("building the mesh failed: ") + e.what());
  }
  if (!status)
  {
    return fail("the input mesh is not valid: " + status.message);
  }
  if (buildReport.unused_points > 0)
  {
    warn(std::to_string(buildReport.unused_points) +
      (buildReport.unused_points == 1 ? " point is" : " points are") +
      " not used by any tetrahedron and dropped from the output.");
  }
  return status;
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::FromCompactMesh(
  const femorph::CompactMesh& mesh, vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const vtkIdType numPoints = static_cast<vtkIdType>(mesh.points.size());
  const vtkIdType numTets = static_cast<vtkIdType>(mesh.tets.size());

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    points->SetPoint(i, mesh.points[i].data());
  }
  output->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  offsets->SetNumberOfValues(numTets + 1);
  connectivity->SetNumberOfValues(4 * numTets);
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    offsets->SetValue(t, 4 * t);
    for (int k = 0; k < 4; ++k)
    {
      connectivity->SetValue(4 * t + k, mesh.tets[t][k]);
    }
  }
  offsets->SetValue(numTets, 4 * numTets);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetCells(VTK_TETRA, cells);

  // Point data: interpolate with the vertex stencils; FEMorph's own arrays
  // are recomputed below, not interpolated.
  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyFieldOff(VertexClassName);
  outPD->InterpolateAllocate(inPD, numPoints);
  vtkNew<vtkIdList> ids;
  ids->Allocate(4);
  const bool hasStencils = mesh.vertex_origin.size() == mesh.points.size();
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    if (!hasStencils)
    {
      outPD->NullData(i);
      continue;
    }
    const femorph::VertexStencil& stencil = mesh.vertex_origin[i];
    double weights[4];
    ids->Reset();
    for (int k = 0; k < 4; ++k)
    {
      if (stencil.ids[k] >= 0 && stencil.weights[k] != 0)
      {
        weights[ids->GetNumberOfIds()] = stencil.weights[k];
        ids->InsertNextId(stencil.ids[k]);
      }
    }
    if (ids->GetNumberOfIds() == 1 && weights[0] == 1)
    {
      // An input vertex: exact copy (no rounding of integer or 64-bit data).
      outPD->CopyData(inPD, ids->GetId(0), i);
    }
    else if (ids->GetNumberOfIds() > 0)
    {
      outPD->InterpolatePoint(inPD, i, ids, weights);
    }
    else
    {
      outPD->NullData(i);
    }
  }

  // Cell data: each tet inherits the values of the input tet it comes from.
  vtkCellData* inCD = input->GetCellData();
  vtkCellData* outCD = output->GetCellData();
  const bool inputHadRegions = inCD->GetArray(FaceRegionName) != nullptr;
  outCD->CopyFieldOff(FaceRegionName);
  outCD->CopyAllocate(inCD, numTets);
  const vtkIdType numInputCells = input->GetNumberOfCells();
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    const vtkIdType origin =
      t < static_cast<vtkIdType>(mesh.tet_origin.size()) ? mesh.tet_origin[t] : -1;
    if (origin >= 0 && origin < numInputCells)
    {
      outCD->CopyData(inCD, origin, t);
    }
    else
    {
      outCD->NullData(t);
    }
  }
  // The copy flags persist in the output's attribute objects: restore them so
  // downstream copies of this output carry the arrays added below.
  outPD->CopyFieldOn(VertexClassName);
  outCD->CopyFieldOn(FaceRegionName);

  bool anyRegion = false;
  for (const femorph::Tet& regions : mesh.face_regions)
  {
    for (femorph::index_t r : regions)
    {
      anyRegion = anyRegion || r >= 0;
    }
  }
  if ((anyRegion || inputHadRegions) &&
    static_cast<vtkIdType>(mesh.face_regions.size()) == numTets)
  {
    vtkNew<vtkIntArray> regions;
    regions->SetName(FaceRegionName);
    regions->SetNumberOfComponents(4);
    regions->SetNumberOfTuples(numTets);
    for (vtkIdType t = 0; t < numTets; ++t)
    {
      for (int f = 0; f < 4; ++f)
      {
        regions->SetTypedComponent(t, f, mesh.face_regions[t][f]);
      }
    }
    outCD->AddArray(regions);
  }

  if (static_cast<vtkIdType>(mesh.vertex_classes.size()) == numPoints)
  {
    vtkNew<vtkUnsignedCharArray> classes;
    classes->SetName(VertexClassName);
    classes->SetNumberOfTuples(numPoints);
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      classes->SetValue(i, static_cast<unsigned char>(mesh.vertex_classes[i]));
    }
    outPD->AddArray(classes);
  }

  output->GetFieldData()->PassData(input->GetFieldData());
}
