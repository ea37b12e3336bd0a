#include "vtkFEMorphMeshConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "common/huge_pages.h"
#include "common/parallel.h"

#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace
{
/// The shape every per-cell array must have: one component, one tuple per
/// cell; `what` starts the message.
femorph::Status OneValuePerCell(vtkDataArray* values, vtkIdType numCells, const std::string& what)
{
  if (values->GetNumberOfTuples() != numCells || values->GetNumberOfComponents() != 1)
  {
    return femorph::Status::failure(what + "that cell array has " +
      std::to_string(values->GetNumberOfTuples()) + " values of " +
      std::to_string(values->GetNumberOfComponents()) + " components; one value per cell (" +
      std::to_string(numCells) + ") is needed.");
  }
  return femorph::Status::success();
}

// The core numbers vertices and tets with 32-bit ids.
constexpr vtkIdType MaxCoreIndex = std::numeric_limits<femorph::index_t>::max();

constexpr int UnknownCellType = -2;

/// The number of points of a VTK cell type with a fixed one, -1 for types
/// with any number (polygons, polyhedra, Lagrange and Bezier cells...),
/// UnknownCellType for a number that is no VTK cell type.
int PointsOfCellType(int type)
{
  switch (type)
  {
    case VTK_EMPTY_CELL: return 0;
    case VTK_VERTEX: return 1;
    case VTK_LINE: return 2;
    case VTK_TRIANGLE: return 3;
    case VTK_PIXEL:
    case VTK_QUAD:
    case VTK_TETRA: return 4;
    case VTK_PYRAMID: return 5;
    case VTK_WEDGE: return 6;
    case VTK_VOXEL:
    case VTK_HEXAHEDRON: return 8;
    case VTK_PENTAGONAL_PRISM: return 10;
    case VTK_HEXAGONAL_PRISM: return 12;
    case VTK_QUADRATIC_EDGE: return 3;
    case VTK_QUADRATIC_TRIANGLE: return 6;
    case VTK_QUADRATIC_QUAD: return 8;
    case VTK_QUADRATIC_TETRA: return 10;
    case VTK_QUADRATIC_HEXAHEDRON: return 20;
    case VTK_QUADRATIC_WEDGE: return 15;
    case VTK_QUADRATIC_PYRAMID: return 13;
    case VTK_BIQUADRATIC_QUAD: return 9;
    case VTK_TRIQUADRATIC_HEXAHEDRON: return 27;
    case VTK_TRIQUADRATIC_PYRAMID: return 19;
    case VTK_QUADRATIC_LINEAR_QUAD: return 6;
    case VTK_QUADRATIC_LINEAR_WEDGE: return 12;
    case VTK_BIQUADRATIC_QUADRATIC_WEDGE: return 18;
    case VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON: return 24;
    case VTK_BIQUADRATIC_TRIANGLE: return 7;
    case VTK_CUBIC_LINE: return 4;
    case VTK_POLY_VERTEX:
    case VTK_POLY_LINE:
    case VTK_TRIANGLE_STRIP:
    case VTK_POLYGON:
    case VTK_QUADRATIC_POLYGON:
    case VTK_CONVEX_POINT_SET:
    case VTK_POLYHEDRON:
    case VTK_PARAMETRIC_CURVE:
    case VTK_PARAMETRIC_SURFACE:
    case VTK_PARAMETRIC_TRI_SURFACE:
    case VTK_PARAMETRIC_QUAD_SURFACE:
    case VTK_PARAMETRIC_TETRA_REGION:
    case VTK_PARAMETRIC_HEX_REGION:
    case VTK_HIGHER_ORDER_EDGE:
    case VTK_HIGHER_ORDER_TRIANGLE:
    case VTK_HIGHER_ORDER_QUAD:
    case VTK_HIGHER_ORDER_POLYGON:
    case VTK_HIGHER_ORDER_TETRAHEDRON:
    case VTK_HIGHER_ORDER_WEDGE:
    case VTK_HIGHER_ORDER_PYRAMID:
    case VTK_HIGHER_ORDER_HEXAHEDRON:
    case VTK_LAGRANGE_CURVE:
    case VTK_LAGRANGE_TRIANGLE:
    case VTK_LAGRANGE_QUADRILATERAL:
    case VTK_LAGRANGE_TETRAHEDRON:
    case VTK_LAGRANGE_HEXAHEDRON:
    case VTK_LAGRANGE_WEDGE:
    case VTK_LAGRANGE_PYRAMID:
    case VTK_BEZIER_CURVE:
    case VTK_BEZIER_TRIANGLE:
    case VTK_BEZIER_QUADRILATERAL:
    case VTK_BEZIER_TETRAHEDRON:
    case VTK_BEZIER_HEXAHEDRON:
    case VTK_BEZIER_WEDGE:
    case VTK_BEZIER_PYRAMID: return -1;
    default: return UnknownCellType;
  }
}
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
  const unsigned char* types = numCells > 0 ? input->GetCellTypesArray()->GetPointer(0) : nullptr;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    ++counts[types[c]];
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
std::string vtkFEMorphMeshConversion::CheckGrid(
  vtkUnstructuredGrid* grid, CellSet cells, const std::string& gridName)
{
  if (!grid)
  {
    return gridName + " is missing.";
  }
  const vtkIdType numCells = grid->GetNumberOfCells();
  const vtkIdType numPoints = grid->GetNumberOfPoints();
  if (numCells > 0 && (!grid->GetPoints() || numPoints == 0))
  {
    return gridName + " has " + std::to_string(numCells) + (numCells == 1 ? " cell" : " cells") +
      " but no points.";
  }
  if (numPoints > MaxCoreIndex || numCells > MaxCoreIndex / 4)
  {
    return gridName + " is too large (" + std::to_string(numPoints) + " points, " +
      std::to_string(numCells) + " cells; the limit is " + std::to_string(MaxCoreIndex / 4) +
      " cells and " + std::to_string(MaxCoreIndex) + " points).";
  }
  if (const vtkIdType bad = CountNonFinitePoints(grid->GetPoints()))
  {
    return std::to_string(bad) + (bad == 1 ? " point of " : " points of ") + gridName +
      (bad == 1 ? " has" : " have") + " NaN or infinite coordinates; fix or remove " +
      (bad == 1 ? "it" : "them") + " first.";
  }

  std::string others;
  if (cells == CellSet::Tetrahedra && DescribeOtherCells(grid, VTK_TETRA, others) > 0)
  {
    return gridName + " has " + others +
      "; this filter reads tetrahedra only (ParaView's Tetrahedralize filter converts "
      "them).";
  }
  if (cells == CellSet::Linear3D)
  {
    std::array<vtkIdType, 256> counts{};
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      ++counts[static_cast<unsigned char>(grid->GetCellType(c))];
    }
    for (int type : { VTK_TETRA, VTK_PYRAMID, VTK_WEDGE, VTK_HEXAHEDRON, VTK_VOXEL })
    {
      counts[type] = 0;
    }
    others = DescribeCellCounts(counts);
    if (!others.empty())
    {
      return gridName + " has " + others +
        "; this filter reads linear hexahedra, voxels, wedges, pyramids and tetrahedra only "
        "(Extract Cells By Type selects them; higher-order cells must be made linear first).";
    }
  }

  // Attribute arrays are copied and interpolated tuple by tuple: a short
  // one would be read past its end, a long one passed on to a mesh it does
  // not fit.
  for (int kind = 0; kind < 2; ++kind)
  {
    vtkDataSetAttributes* data = kind == 0
      ? static_cast<vtkDataSetAttributes*>(grid->GetPointData())
      : static_cast<vtkDataSetAttributes*>(grid->GetCellData());
    const vtkIdType expected = kind == 0 ? numPoints : numCells;
    for (int a = 0; a < data->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = data->GetAbstractArray(a);
      if (array && array->GetNumberOfTuples() != expected)
      {
        const char* name = array->GetName();
        return std::string(kind == 0 ? "the point array '" : "the cell array '") +
          (name ? name : "") + "' of " + gridName + " has " +
          std::to_string(array->GetNumberOfTuples()) +
          (array->GetNumberOfTuples() == 1 ? " value for " : " values for ") +
          std::to_string(expected) + (kind == 0 ? " points" : " cells") +
          "; the data is corrupt (remove the array or fix its length).";
      }
    }
  }

  // The point count of each linear cell type, and point ids in range, read
  // from the cell array's own storage (32 or 64 bit): no call per cell.
  if (numCells == 0)
  {
    return std::string();
  }
  const unsigned char* types = grid->GetCellTypesArray()->GetPointer(0);
  const auto checkCells = [&](const auto* offsets, const auto* connectivity) -> std::string {
    vtkIdType totalIds = 0;
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      const int type = types[c];
      const vtkIdType npts = static_cast<vtkIdType>(offsets[c + 1] - offsets[c]);
      const auto* pts = connectivity + offsets[c];
      const int expected = PointsOfCellType(type);
      if (expected == UnknownCellType)
      {
        return "cell " + std::to_string(c) + " of " + gridName + " has the type " +
          std::to_string(type) + ", which is no VTK cell type; the file is corrupt.";
      }
      if (expected >= 0 && npts != expected)
      {
        return "cell " + std::to_string(c) + " of " + gridName + " is a " + CellTypeName(type) +
          " with " + std::to_string(npts) + " points instead of " + std::to_string(expected) +
          "; the file is corrupt.";
      }
      totalIds += npts;
      if (totalIds > MaxCoreIndex)
      {
        return gridName + " is too large (more than " + std::to_string(MaxCoreIndex) +
          " point ids in its cells).";
      }
      for (vtkIdType k = 0; k < npts; ++k)
      {
        if (pts[k] < 0 || pts[k] >= numPoints)
        {
          return "cell " + std::to_string(c) + " of " + gridName + " refers to point " +
            std::to_string(static_cast<vtkIdType>(pts[k])) + ", but there are " +
            std::to_string(numPoints) + " points; the file is corrupt.";
        }
      }
    }
    return std::string();
  };
  vtkCellArray* cellArray = grid->GetCells();
  return cellArray->IsStorage64Bit()
    ? checkCells(cellArray->GetOffsetsArray64()->GetPointer(0),
        cellArray->GetConnectivityArray64()->GetPointer(0))
    : checkCells(cellArray->GetOffsetsArray32()->GetPointer(0),
        cellArray->GetConnectivityArray32()->GetPointer(0));
}

//------------------------------------------------------------------------------
std::vector<femorph::Vec3> vtkFEMorphMeshConversion::ReadPoints(vtkUnstructuredGrid* grid)
{
  const vtkIdType numPoints = grid->GetNumberOfPoints();
  std::vector<femorph::Vec3> points;
  points.reserve(static_cast<std::size_t>(numPoints));
  femorph::advise_huge_pages(points.data(), static_cast<std::size_t>(numPoints) * sizeof(femorph::Vec3));
  points.resize(static_cast<std::size_t>(numPoints));
  // Double coordinates in one block (the common case) are copied as they are.
  vtkDoubleArray* doubles =
    numPoints > 0 ? vtkDoubleArray::FastDownCast(grid->GetPoints()->GetData()) : nullptr;
  if (doubles && doubles->GetNumberOfComponents() == 3)
  {
    const double* xyz = doubles->GetPointer(0);
    femorph::parallel_for(static_cast<long>(numPoints), [&](long i) {
      points[static_cast<std::size_t>(i)] = femorph::Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    });
    return points;
  }
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    grid->GetPoint(i, points[static_cast<std::size_t>(i)].data());
  }
  return points;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPoints> vtkFEMorphMeshConversion::NewPoints(const std::vector<femorph::Vec3>& points)
{
  auto out = vtkSmartPointer<vtkPoints>::New();
  out->SetDataTypeToDouble();
  out->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    out->SetPoint(static_cast<vtkIdType>(i), points[i].data());
  }
  return out;
}

//------------------------------------------------------------------------------
femorph::Status vtkFEMorphMeshConversion::ReadTetGrid(
  vtkUnstructuredGrid* grid, std::vector<femorph::Vec3>& points, std::vector<femorph::Tet>& tets)
{
  points.clear();
  tets.clear();
  const std::string problem = CheckGrid(grid, CellSet::Tetrahedra);
  if (!problem.empty())
  {
    return femorph::Status::failure(problem);
  }
  points = ReadPoints(grid);
  const vtkIdType numCells = grid->GetNumberOfCells();
  tets.reserve(static_cast<std::size_t>(numCells));
  femorph::advise_huge_pages(tets.data(), static_cast<std::size_t>(numCells) * sizeof(femorph::Tet));
  tets.resize(static_cast<std::size_t>(numCells));
  // The cell array's own storage (offsets and connectivity, 32 or 64 bit):
  // no call per cell.
  vtkCellArray* cells = grid->GetCells();
  const auto copy = [&tets, numCells](const auto* offsets, const auto* connectivity) {
    femorph::parallel_for(static_cast<long>(numCells), [&](long c) {
      const auto* pts = connectivity + offsets[c];
      for (int k = 0; k < 4; ++k)
      {
        tets[static_cast<std::size_t>(c)][k] = static_cast<femorph::index_t>(pts[k]);
      }
    });
  };
  if (cells->IsStorage64Bit())
  {
    copy(cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0));
  }
  else
  {
    copy(cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
  }
  return femorph::Status::success();
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::ReadLinearCells(vtkUnstructuredGrid* grid, femorph::MixedCells& cells,
  std::vector<vtkIdType>* cellIds, std::array<vtkIdType, 256>* skipped)
{
  cells = femorph::MixedCells();
  if (cellIds)
  {
    cellIds->clear();
  }
  const vtkIdType numCells = grid->GetNumberOfCells();
  cells.kinds.reserve(static_cast<std::size_t>(numCells));
  cells.offsets.reserve(static_cast<std::size_t>(numCells) + 1);
  // VTK_VOXEL's node order -> VTK_HEXAHEDRON's.
  constexpr int voxelToHex[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const int type = grid->GetCellType(c);
    femorph::CellKind kind = femorph::CellKind::Tetra;
    switch (type)
    {
      case VTK_TETRA: break;
      case VTK_PYRAMID: kind = femorph::CellKind::Pyramid; break;
      case VTK_WEDGE: kind = femorph::CellKind::Wedge; break;
      case VTK_HEXAHEDRON:
      case VTK_VOXEL: kind = femorph::CellKind::Hexahedron; break;
      default:
        if (skipped)
        {
          ++(*skipped)[static_cast<unsigned char>(type)];
        }
        continue;
    }
    grid->GetCellPoints(c, npts, pts);
    femorph::index_t nodes[8];
    const int n = femorph::cell_node_count(kind);
    for (int k = 0; k < n; ++k)
    {
      nodes[k] = static_cast<femorph::index_t>(pts[type == VTK_VOXEL ? voxelToHex[k] : k]);
    }
    cells.add(kind, nodes);
    if (cellIds)
    {
      cellIds->push_back(c);
    }
  }
}

//------------------------------------------------------------------------------
femorph::Status vtkFEMorphMeshConversion::ReadCellMask(vtkUnstructuredGrid* grid,
  const std::string& name, const std::string& property, std::vector<std::uint8_t>& mask)
{
  mask.clear();
  const std::string what = property + " is '" + name + "', but ";
  vtkAbstractArray* array = grid->GetCellData()->GetAbstractArray(name.c_str());
  if (!array)
  {
    return femorph::Status::failure(what + "the input has no cell array of that name.");
  }
  vtkDataArray* values = vtkDataArray::SafeDownCast(array);
  if (!values)
  {
    return femorph::Status::failure(what + "that cell array is not numeric (it holds " +
      array->GetDataTypeAsString() + " values).");
  }
  const vtkIdType numCells = grid->GetNumberOfCells();
  const femorph::Status shape = OneValuePerCell(values, numCells, what);
  if (!shape)
  {
    return shape;
  }
  mask.resize(static_cast<std::size_t>(numCells));
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const double v = values->GetComponent(c, 0);
    if (!std::isfinite(v))
    {
      mask.clear();
      return femorph::Status::failure(what + "that cell array has the value " +
        std::to_string(v) + " at cell " + std::to_string(c) + ".");
    }
    mask[static_cast<std::size_t>(c)] = v != 0;
  }
  return femorph::Status::success();
}

//------------------------------------------------------------------------------
namespace
{
/// Integer VTK data types: ids and labels, which have no weighted mean.
bool IsIntegerType(int type)
{
  switch (type)
  {
    case VTK_BIT:
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
    case VTK_UNSIGNED_CHAR:
    case VTK_SHORT:
    case VTK_UNSIGNED_SHORT:
    case VTK_INT:
    case VTK_UNSIGNED_INT:
    case VTK_LONG:
    case VTK_UNSIGNED_LONG:
    case VTK_LONG_LONG:
    case VTK_UNSIGNED_LONG_LONG:
    case VTK_ID_TYPE:
      return true;
    default:
      return false;
  }
}
}

femorph::Status vtkFEMorphMeshConversion::ReadCellIds(vtkUnstructuredGrid* grid,
  const std::string& name, const std::string& property, std::vector<int>& ids)
{
  ids.clear();
  const std::string what = property + " is '" + name + "', but ";
  vtkAbstractArray* array = grid->GetCellData()->GetAbstractArray(name.c_str());
  if (!array)
  {
    const bool onPoints = grid->GetPointData()->GetAbstractArray(name.c_str()) != nullptr;
    return femorph::Status::failure(what + "the input has no cell array of that name" +
      (onPoints ? " (it is a point array; the ids are per cell)." : "."));
  }
  vtkDataArray* values = vtkDataArray::SafeDownCast(array);
  if (!values || !IsIntegerType(values->GetDataType()))
  {
    return femorph::Status::failure(what + "that cell array holds " + array->GetDataTypeAsString() +
      " values; ids need an integer array (int, short, char, long ...).");
  }
  const vtkIdType numCells = grid->GetNumberOfCells();
  const femorph::Status shape = OneValuePerCell(values, numCells, what);
  if (!shape)
  {
    return shape;
  }
  ids.resize(static_cast<std::size_t>(numCells));
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const double v = values->GetComponent(c, 0);
    if (!(v >= 0 && v <= std::numeric_limits<int>::max()))
    {
      ids.clear();
      std::ostringstream os;
      os << what << "that cell array has the value " << std::fixed << std::setprecision(0) << v
         << " at cell " << c << "; ids must be in [0, " << std::numeric_limits<int>::max() << "].";
      return femorph::Status::failure(os.str());
    }
    ids[static_cast<std::size_t>(c)] = static_cast<int>(v);
  }
  return femorph::Status::success();
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::InterpolatePointData(vtkUnstructuredGrid* input,
  const std::vector<femorph::VertexStencil>& stencils, vtkUnstructuredGrid* output)
{
  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  const vtkIdType numPoints = static_cast<vtkIdType>(stencils.size());
  const vtkIdType numInputPoints = input->GetNumberOfPoints();
  outPD->InterpolateAllocate(inPD, numPoints);
  // Integer and non-numeric arrays, paired with their input array by name,
  // take the largest weight's tuple after the interpolation.
  std::vector<std::pair<vtkAbstractArray*, vtkAbstractArray*>> nearest;
  for (int a = 0; a < outPD->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* out = outPD->GetAbstractArray(a);
    auto* data = vtkDataArray::SafeDownCast(out);
    vtkAbstractArray* in = out->GetName() ? inPD->GetAbstractArray(out->GetName()) : nullptr;
    if (in && (!data || IsIntegerType(data->GetDataType())))
    {
      nearest.emplace_back(out, in);
    }
  }
  vtkNew<vtkIdList> ids;
  ids->Allocate(4);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    const femorph::VertexStencil& stencil = stencils[static_cast<std::size_t>(i)];
    double weights[4];
    vtkIdType largest = -1;
    double largestWeight = 0;
    ids->Reset();
    for (int k = 0; k < 4; ++k)
    {
      const vtkIdType id = stencil.ids[k];
      if (id >= 0 && id < numInputPoints && stencil.weights[k] != 0)
      {
        weights[ids->GetNumberOfIds()] = stencil.weights[k];
        ids->InsertNextId(id);
        if (largest < 0 || stencil.weights[k] > largestWeight)
        {
          largest = id;
          largestWeight = stencil.weights[k];
        }
      }
    }
    if (ids->GetNumberOfIds() == 1 && weights[0] == 1)
    {
      outPD->CopyData(inPD, ids->GetId(0), i);
    }
    else if (ids->GetNumberOfIds() > 0)
    {
      outPD->InterpolatePoint(inPD, i, ids, weights);
      for (const auto& pair : nearest)
      {
        pair.first->InsertTuple(i, largest, pair.second);
      }
    }
    else
    {
      outPD->NullData(i);
    }
  }
}

//------------------------------------------------------------------------------
femorph::Status vtkFEMorphMeshConversion::ToTetMesh(vtkUnstructuredGrid* input,
  const femorph::BuildOptions& options, femorph::TetMesh& mesh, femorph::BuildReport* report,
  std::vector<std::string>* warnings)
{
  mesh = femorph::TetMesh();
  if (!input || input->GetNumberOfCells() == 0)
  {
    return femorph::Status::failure("the input has no cells.");
  }
  std::vector<femorph::Vec3> points;
  std::vector<femorph::Tet> tets;
  const femorph::Status read = ReadTetGrid(input, points, tets);
  if (!read)
  {
    return read;
  }

  femorph::BuildReport localReport;
  femorph::BuildReport& buildReport = report ? *report : localReport;
  const femorph::Status status = mesh.build(std::move(points), std::move(tets), options, &buildReport);
  if (!status)
  {
    return femorph::Status::failure("the input mesh is not valid: " + status.message + ".");
  }
  if (buildReport.unused_points > 0 && warnings)
  {
    warnings->push_back(std::to_string(buildReport.unused_points) +
      (buildReport.unused_points == 1 ? " point is" : " points are") +
      " not used by any tetrahedron; FEMorph leaves " +
      (buildReport.unused_points == 1 ? "it" : "them") + " out of the mesh it works on.");
  }
  return status;
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::SetTetCells(
  vtkUnstructuredGrid* output, const std::vector<femorph::Tet>& tets)
{
  const vtkIdType numTets = static_cast<vtkIdType>(tets.size());
  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  offsets->SetNumberOfValues(numTets + 1);
  connectivity->SetNumberOfValues(4 * numTets);
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    offsets->SetValue(t, 4 * t);
    for (int k = 0; k < 4; ++k)
    {
      connectivity->SetValue(4 * t + k, tets[static_cast<std::size_t>(t)][k]);
    }
  }
  offsets->SetValue(numTets, 4 * numTets);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetCells(VTK_TETRA, cells);
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::SetMixedCells(
  vtkUnstructuredGrid* output, const femorph::MixedCells& cells)
{
  const vtkIdType nc = cells.size();
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nc + 1);
  for (vtkIdType c = 0; c <= nc; ++c)
  {
    offsets->SetValue(c, cells.offsets[static_cast<std::size_t>(c)]);
  }
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(cells.connectivity.size()));
  for (std::size_t i = 0; i < cells.connectivity.size(); ++i)
  {
    connectivity->SetValue(static_cast<vtkIdType>(i), cells.connectivity[i]);
  }
  vtkNew<vtkCellArray> cellArray;
  cellArray->SetData(offsets, connectivity);
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(nc);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    int type = VTK_TETRA;
    switch (cells.kinds[static_cast<std::size_t>(c)])
    {
      case femorph::CellKind::Hexahedron: type = VTK_HEXAHEDRON; break;
      case femorph::CellKind::Wedge: type = VTK_WEDGE; break;
      case femorph::CellKind::Pyramid: type = VTK_PYRAMID; break;
      case femorph::CellKind::Tetra: break;
    }
    types->SetValue(c, static_cast<unsigned char>(type));
  }
  output->SetCells(types, cellArray);
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::CopySourceCellData(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, const std::vector<femorph::index_t>& source)
{
  vtkCellData* inCD = input->GetCellData();
  vtkCellData* outCD = output->GetCellData();
  const vtkIdType numCells = static_cast<vtkIdType>(source.size());
  const vtkIdType numInputCells = input->GetNumberOfCells();
  outCD->CopyAllocate(inCD, numCells);
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const vtkIdType from = source[static_cast<std::size_t>(c)];
    if (from >= 0 && from < numInputCells)
    {
      outCD->CopyData(inCD, from, c);
    }
    else
    {
      outCD->NullData(c);
    }
  }
}

//------------------------------------------------------------------------------
void vtkFEMorphMeshConversion::FromCompactMesh(
  const femorph::CompactMesh& mesh, vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  const vtkIdType numPoints = static_cast<vtkIdType>(mesh.points.size());
  const vtkIdType numTets = static_cast<vtkIdType>(mesh.tets.size());

  output->SetPoints(NewPoints(mesh.points));
  SetTetCells(output, mesh.tets);

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
  if (static_cast<vtkIdType>(mesh.tet_origin.size()) == numTets)
  {
    CopySourceCellData(input, output, mesh.tet_origin);
  }
  else
  {
    CopySourceCellData(input, output, std::vector<femorph::index_t>(mesh.tets.size(), -1));
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
