#include "vtkFEMorphHexToTet.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "hex/hex_to_tet.h"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <new>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphHexToTet);

namespace
{
const char* const Label = "FEMorph Hex To Tet";

// At most this many cell ids in a message.
constexpr std::size_t MaxListedIds = 10;

std::string Plural(std::size_t n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string ListIds(const std::vector<femorph::index_t>& ids)
{
  std::ostringstream os;
  for (std::size_t i = 0; i < ids.size() && i < MaxListedIds; ++i)
  {
    os << (i ? " " : "") << ids[i];
  }
  if (ids.size() > MaxListedIds)
  {
    os << " ...";
  }
  return os.str();
}

void AddCount(vtkFieldData* fd, const char* name, vtkIdType value)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

std::string TypeName(int type, bool mirrored)
{
  return std::string(femorph::to_string(static_cast<femorph::HexDecompositionType>(type))) +
    (mirrored ? "-" : "+");
}
}

//------------------------------------------------------------------------------
vtkFEMorphHexToTet::vtkFEMorphHexToTet()
{
  const femorph::HexToTetParams defaults;
  this->Conforming = defaults.conforming ? 1 : 0;
  this->DecompositionType = static_cast<int>(defaults.type);
  this->Mirrored = defaults.mirrored ? 1 : 0;
}

vtkFEMorphHexToTet::~vtkFEMorphHexToTet() = default;

//------------------------------------------------------------------------------
void vtkFEMorphHexToTet::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Conforming: " << (this->Conforming ? "On" : "Off") << "\n";
  os << indent << "DecompositionType: " << this->DecompositionType << " ("
     << femorph::to_string(static_cast<femorph::HexDecompositionType>(this->DecompositionType))
     << ")\n";
  os << indent << "Mirrored: " << (this->Mirrored ? "On" : "Off") << "\n";
  os << indent << "AllowInverted: " << (this->AllowInverted ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
int vtkFEMorphHexToTet::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphHexToTet::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro(<< Label << " needs a vtkUnstructuredGrid input.");
    return 0;
  }
  output->Initialize();

  const vtkIdType numCells = input->GetNumberOfCells();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numCells == 0)
  {
    vtkErrorMacro(<< Label << ": the input has no cells (" << Plural(numPoints, "point", "points")
                  << "); there is nothing to split.");
    return 0;
  }

  // Cell types: the linear 3D cells the core splits, voxels as hexahedra.
  std::array<vtkIdType, 256> rejected{};
  vtkIdType numRejected = 0, connectivitySize = 0;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const int type = input->GetCellType(c);
    switch (type)
    {
      case VTK_TETRA: connectivitySize += 4; break;
      case VTK_PYRAMID: connectivitySize += 5; break;
      case VTK_WEDGE: connectivitySize += 6; break;
      case VTK_HEXAHEDRON:
      case VTK_VOXEL: connectivitySize += 8; break;
      default:
        ++rejected[static_cast<unsigned char>(type)];
        ++numRejected;
    }
  }
  if (numRejected > 0)
  {
    vtkErrorMacro(<< Label
                  << " accepts linear hexahedra, voxels, wedges, pyramids and tetrahedra only; "
                     "the input has "
                  << vtkFEMorphMeshConversion::DescribeCellCounts(rejected)
                  << " of other types. Extract the 3D linear cells first (e.g. Extract Cells By "
                     "Type), or convert higher-order cells to linear ones.");
    return 0;
  }
  constexpr vtkIdType maxIndex = std::numeric_limits<femorph::index_t>::max();
  if (numPoints > maxIndex || connectivitySize > maxIndex)
  {
    vtkErrorMacro(<< Label << " handles up to " << maxIndex
                  << " points and cell nodes; the input has " << numPoints << " points and "
                  << connectivitySize << " cell nodes.");
    return 0;
  }
  if (const vtkIdType bad = vtkFEMorphMeshConversion::CountNonFinitePoints(input->GetPoints()))
  {
    vtkErrorMacro(<< Label << ": " << Plural(bad, "point has", "points have")
                  << " NaN or infinite coordinates; fix or remove them first.");
    return 0;
  }

  femorph::HexToTetParams params;
  params.conforming = this->Conforming != 0;
  params.type = static_cast<femorph::HexDecompositionType>(
    std::clamp(this->DecompositionType, static_cast<int>(TYPE_A), static_cast<int>(TYPE_F)));
  params.mirrored = this->Mirrored != 0;

  femorph::HexToTetResult result;
  try
  {
    this->UpdateProgress(0.0);
    std::vector<femorph::Vec3> points(static_cast<std::size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      input->GetPoint(i, points[i].data());
    }
    femorph::MixedCells cells;
    cells.kinds.reserve(static_cast<std::size_t>(numCells));
    cells.offsets.reserve(static_cast<std::size_t>(numCells) + 1);
    cells.connectivity.reserve(static_cast<std::size_t>(connectivitySize));
    // VTK_VOXEL's node order -> VTK_HEXAHEDRON's.
    constexpr int voxelToHex[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      const int type = input->GetCellType(c);
      femorph::CellKind kind = femorph::CellKind::Hexahedron;
      switch (type)
      {
        case VTK_TETRA: kind = femorph::CellKind::Tetra; break;
        case VTK_PYRAMID: kind = femorph::CellKind::Pyramid; break;
        case VTK_WEDGE: kind = femorph::CellKind::Wedge; break;
        default: break;
      }
      input->GetCellPoints(c, ids);
      const int expected = femorph::cell_node_count(kind);
      if (ids->GetNumberOfIds() != expected)
      {
        vtkErrorMacro(<< Label << ": cell " << c << " is a "
                      << vtkFEMorphMeshConversion::CellTypeName(type) << " with "
                      << ids->GetNumberOfIds() << " points instead of " << expected
                      << "; the input is corrupt.");
        return 0;
      }
      femorph::index_t nodes[8];
      for (int k = 0; k < expected; ++k)
      {
        nodes[k] = static_cast<femorph::index_t>(ids->GetId(type == VTK_VOXEL ? voxelToHex[k] : k));
      }
      cells.add(kind, nodes);
    }
    this->UpdateProgress(0.2);
    if (this->CheckAbort())
    {
      return 1;
    }

    const femorph::Status status = femorph::decompose_to_tetrahedra(points, cells, params, result);
    if (!status)
    {
      vtkErrorMacro(<< Label << ": " << status.message << ".");
      return 0;
    }
  }
  catch (const std::bad_alloc&)
  {
    vtkErrorMacro(<< Label << ": out of memory for " << numCells << " cells.");
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< Label << " failed: " << e.what());
    return 0;
  }
  this->UpdateProgress(0.7);
  if (this->CheckAbort())
  {
    return 1;
  }

  if (result.inverted_cells > 0)
  {
    const std::string what = Plural(result.inverted_cells, "input cell gives", "input cells give") +
      " tetrahedra of zero or negative volume (cells " + ListIds(result.inverted) + ")";
    const char* why = params.conforming
      ? ": no triangulation with the conforming diagonals avoids one, so they are inverted or "
        "badly distorted"
      : ": these cells are inverted or too distorted for type ";
    if (!this->AllowInverted)
    {
      vtkErrorMacro(<< Label << ": " << what << why
                    << (params.conforming ? "" : TypeName(this->DecompositionType, params.mirrored))
                    << ". Fix the mesh, or turn on AllowInverted to get the tetrahedra marked in "
                       "the Inverted array.");
      return 0;
    }
    vtkWarningMacro(<< Label << ": " << what << why
                    << (params.conforming ? "" : TypeName(this->DecompositionType, params.mirrored))
                    << "; they are marked in the Inverted array.");
  }
  if (result.nonconforming_faces > 0)
  {
    if (params.conforming)
    {
      vtkWarningMacro(<< Label << ": "
                      << Plural(result.nonconforming_faces, "quad face", "quad faces")
                      << " cut by two input tetrahedra could not keep their diagonal (no "
                         "triangulation of the cell on the other side realises it): the "
                         "tetrahedral mesh is not conforming there.");
    }
    else
    {
      vtkWarningMacro(<< Label << ": "
                      << Plural(result.nonconforming_faces, "quad face is", "quad faces are")
                      << " split along different diagonals on their two sides by the fixed type "
                      << TypeName(this->DecompositionType, params.mirrored)
                      << " (thesis Fig. 4.6): the tetrahedral mesh is not conforming. Turn "
                         "Conforming on for a conforming split.");
    }
  }

  // Cells: VTK_TETRA over the input's points.
  const vtkIdType numTets = static_cast<vtkIdType>(result.tets.size());
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(numTets + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(4 * numTets);
  vtkNew<vtkIdList> sourceIds;
  sourceIds->SetNumberOfIds(numTets);
  vtkNew<vtkIdTypeArray> sourceCell;
  sourceCell->SetName("SourceCell");
  sourceCell->SetNumberOfTuples(numTets);
  vtkNew<vtkSignedCharArray> decomposition;
  decomposition->SetName("DecompositionType");
  decomposition->SetNumberOfTuples(numTets);
  vtkNew<vtkUnsignedCharArray> inverted;
  inverted->SetName("Inverted");
  inverted->SetNumberOfTuples(numTets);
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    offsets->SetValue(t, 4 * t);
    for (int k = 0; k < 4; ++k)
    {
      connectivity->SetValue(4 * t + k, result.tets[t][k]);
    }
    const femorph::index_t c = result.source_cell[t];
    sourceIds->SetId(t, c);
    sourceCell->SetValue(t, c);
    const int type = result.hex_type[c];
    decomposition->SetValue(
      t, static_cast<signed char>(type < 0 ? -1 : type + (result.hex_mirrored[c] == 1 ? 6 : 0)));
    inverted->SetValue(t, result.tet_inverted[t]);
  }
  offsets->SetValue(numTets, 4 * numTets);
  vtkNew<vtkCellArray> tets;
  tets->SetData(offsets, connectivity);

  output->SetPoints(input->GetPoints());
  output->SetCells(VTK_TETRA, tets);
  output->GetPointData()->ShallowCopy(input->GetPointData());
  // Every child gets its parent's tuple (COPYTUPLE: GlobalIds are left out).
  vtkCellData* cd = output->GetCellData();
  cd->CopyAllocate(input->GetCellData(), numTets);
  cd->CopyData(input->GetCellData(), sourceIds, vtkIdType(0));
  cd->AddArray(sourceCell);
  cd->AddArray(decomposition);
  cd->AddArray(inverted);
  // The output owns its field data container (shares the arrays only), so
  // the counts do not reach the input.
  vtkFieldData* fd = output->GetFieldData();
  fd->ShallowCopy(input->GetFieldData());
  AddCount(fd, "NonConformingFaceCount", static_cast<vtkIdType>(result.nonconforming_faces));
  AddCount(fd, "InvertedCellCount", static_cast<vtkIdType>(result.inverted_cells));
  this->UpdateProgress(1.0);
  return 1;
}
