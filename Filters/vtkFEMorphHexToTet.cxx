#include "vtkFEMorphHexToTet.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "hex/hex_to_tet.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphHexToTet);

namespace
{
// At most this many cell ids in a message.
constexpr std::size_t MaxListedIds = 10;

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

std::string TypeName(int type, bool mirrored)
{
  return std::string(femorph::to_string(static_cast<femorph::HexDecompositionType>(type))) +
    (mirrored ? "-" : "+");
}
}

//------------------------------------------------------------------------------
vtkFEMorphHexToTet::vtkFEMorphHexToTet()
  : vtkFEMorphAlgorithm("FEMorph Hex To Tet", Linear3DCells)
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
bool vtkFEMorphHexToTet::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  femorph::HexToTetParams params;
  params.conforming = this->Conforming != 0;
  params.type = static_cast<femorph::HexDecompositionType>(
    std::clamp(this->DecompositionType, static_cast<int>(TYPE_A), static_cast<int>(TYPE_F)));
  params.mirrored = this->Mirrored != 0;

  const std::vector<femorph::Vec3> points = vtkFEMorphMeshConversion::ReadPoints(input);
  femorph::MixedCells cells;
  vtkFEMorphMeshConversion::ReadLinearCells(input, cells);
  if (!this->Progress(0.2))
  {
    return true;
  }
  femorph::HexToTetResult result;
  if (!this->Check(femorph::decompose_to_tetrahedra(points, cells, params, result)))
  {
    return false;
  }
  if (!this->Progress(0.7))
  {
    return true;
  }

  if (result.inverted_cells > 0)
  {
    const std::string what = Plural(result.inverted_cells, "input cell gives", "input cells give") +
      " tetrahedra of zero or negative volume (cells " + ListIds(result.inverted) + ")" +
      (params.conforming
          ? ": no triangulation with the conforming diagonals avoids one, so they are inverted "
            "or badly distorted"
          : ": these cells are inverted or too distorted for type " +
            TypeName(this->DecompositionType, params.mirrored));
    if (!this->AllowInverted)
    {
      this->Fail(what +
        ". Fix the mesh, or turn on AllowInverted to get the tetrahedra marked in the Inverted "
        "array.");
      return false;
    }
    this->Warn(what + "; they are marked in the Inverted array.");
  }
  if (result.nonconforming_faces > 0)
  {
    if (params.conforming)
    {
      this->Warn(Plural(result.nonconforming_faces, "quad face", "quad faces") +
        " cut by two input tetrahedra could not keep their diagonal (no triangulation of the "
        "cell on the other side realises it): the tetrahedral mesh is not conforming there.");
    }
    else
    {
      this->Warn(Plural(result.nonconforming_faces, "quad face is", "quad faces are") +
        " split along different diagonals on their two sides by the fixed type " +
        TypeName(this->DecompositionType, params.mirrored) +
        " (thesis Fig. 4.6): the tetrahedral mesh is not conforming. Turn Conforming on for a "
        "conforming split.");
    }
  }

  // VTK_TETRA cells over the input's points; each takes its cell's data.
  const vtkIdType numTets = static_cast<vtkIdType>(result.tets.size());
  output->SetPoints(input->GetPoints());
  vtkFEMorphMeshConversion::SetTetCells(output, result.tets);
  output->GetPointData()->ShallowCopy(input->GetPointData());
  vtkFEMorphMeshConversion::CopySourceCellData(input, output, result.source_cell);

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
    const femorph::index_t c = result.source_cell[t];
    sourceCell->SetValue(t, c);
    const int type = result.hex_type[c];
    decomposition->SetValue(
      t, static_cast<signed char>(type < 0 ? -1 : type + (result.hex_mirrored[c] == 1 ? 6 : 0)));
    inverted->SetValue(t, result.tet_inverted[t]);
  }
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(sourceCell);
  cd->AddArray(decomposition);
  cd->AddArray(inverted);
  // The output owns its field data container (shares the arrays only), so
  // the counts do not reach the input.
  vtkFieldData* fd = output->GetFieldData();
  fd->ShallowCopy(input->GetFieldData());
  AddCount(fd, "NonConformingFaceCount", static_cast<vtkIdType>(result.nonconforming_faces));
  AddCount(fd, "InvertedCellCount", static_cast<vtkIdType>(result.inverted_cells));
  return true;
}
