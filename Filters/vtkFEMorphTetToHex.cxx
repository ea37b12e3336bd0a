#include "vtkFEMorphTetToHex.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include "hex/tet_to_hex.h"

#include <array>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphTetToHex);

namespace
{
// Output kinds in Table 4.3's order and their names in the field data.
const femorph::CellKind Kinds[4] = { femorph::CellKind::Hexahedron, femorph::CellKind::Wedge,
  femorph::CellKind::Pyramid, femorph::CellKind::Tetra };
const char* const KindNames[4] = { "Hex", "Prism", "Pyramid", "Tet" };

// Hexahedra, prisms, pyramids: one tuple of three counts.
void AddKindCounts(vtkFieldData* fd, const char* name, const std::array<std::size_t, 4>& counts)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(1);
  for (int k = 0; k < 3; ++k)
  {
    a->SetComponentName(k, KindNames[k]);
    a->SetTypedComponent(0, k, static_cast<vtkIdType>(counts[static_cast<int>(Kinds[k])]));
  }
  fd->AddArray(a);
}
}

//------------------------------------------------------------------------------
vtkFEMorphTetToHex::vtkFEMorphTetToHex()
  : vtkFEMorphAlgorithm("FEMorph Tet To Hex", Tetrahedra)
{
  const femorph::TetToHexParams defaults;
  this->QuadAngle = defaults.quad_angle_deg;
  this->MinScaledJacobian = defaults.min_scaled_jacobian;
  this->Hexahedra = defaults.hexahedra ? 1 : 0;
  this->Prisms = defaults.prisms ? 1 : 0;
  this->Pyramids = defaults.pyramids ? 1 : 0;
  this->RefuseNonConformal = defaults.refuse_nonconformal ? 1 : 0;
}

vtkFEMorphTetToHex::~vtkFEMorphTetToHex() = default;

//------------------------------------------------------------------------------
void vtkFEMorphTetToHex::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "QuadAngle: " << this->QuadAngle << "\n";
  os << indent << "MinScaledJacobian: " << this->MinScaledJacobian << "\n";
  os << indent << "Hexahedra: " << (this->Hexahedra ? "On" : "Off") << "\n";
  os << indent << "Prisms: " << (this->Prisms ? "On" : "Off") << "\n";
  os << indent << "Pyramids: " << (this->Pyramids ? "On" : "Off") << "\n";
  os << indent << "RefuseNonConformal: " << (this->RefuseNonConformal ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
bool vtkFEMorphTetToHex::CheckProperties()
{
  return this->CheckRange("QuadAngle", this->QuadAngle, 0, 180, "degrees") &&
    this->CheckRange("MinScaledJacobian", this->MinScaledJacobian, -1, 1);
}

//------------------------------------------------------------------------------
bool vtkFEMorphTetToHex::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  this->Progress(0.0, "converting the mesh");
  std::vector<femorph::Vec3> points;
  std::vector<femorph::Tet> tets;
  if (!this->Check(vtkFEMorphMeshConversion::ReadTetGrid(input, points, tets)))
  {
    return false;
  }

  femorph::TetToHexParams params;
  params.quad_angle_deg = this->QuadAngle;
  params.min_scaled_jacobian = this->MinScaledJacobian;
  params.hexahedra = this->Hexahedra != 0;
  params.prisms = this->Prisms != 0;
  params.pyramids = this->Pyramids != 0;
  params.refuse_nonconformal = this->RefuseNonConformal != 0;
  params.progress = this->ProgressRange(0.05, 0.95);
  femorph::TetToHexResult result;
  const femorph::Status status = femorph::recombine_tetrahedra(points, tets, params, result);
  if (this->WasAborted())
  {
    return true;
  }
  if (!status)
  {
    this->Fail(status.message +
      " (cell ids are the input's; FEMorph Mesh Quality shows inverted and flat tetrahedra).");
    return false;
  }

  this->Progress(0.95, "writing the output");
  const femorph::MixedCells& cells = result.cells;
  const vtkIdType nc = cells.size();
  output->SetPoints(input->GetPoints());
  vtkFEMorphMeshConversion::SetMixedCells(output, cells);
  output->GetPointData()->PassData(input->GetPointData());

  // Cell data: each cell takes its first source tet's values.
  std::vector<femorph::index_t> firstSource(static_cast<std::size_t>(nc));
  for (vtkIdType c = 0; c < nc; ++c)
  {
    firstSource[c] = result.source_tets[result.source_offsets[c]];
  }
  vtkFEMorphMeshConversion::CopySourceCellData(input, output, firstSource);
  vtkCellData* outCD = output->GetCellData();
  vtkNew<vtkDoubleArray> jacobian;
  jacobian->SetName("ScaledJacobian");
  jacobian->SetNumberOfTuples(nc);
  vtkNew<vtkIntArray> sources;
  sources->SetName("SourceTets");
  sources->SetNumberOfTuples(nc);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    jacobian->SetValue(c, result.min_scaled_jacobian[c]);
    sources->SetValue(c, result.source_offsets[c + 1] - result.source_offsets[c]);
  }
  outCD->AddArray(jacobian);
  outCD->AddArray(sources);
  outCD->SetActiveScalars("ScaledJacobian");

  // Field data: Table 4.3 (volume and number of each polyhedron, ratios).
  const femorph::TetToHexStats& stats = result.stats;
  vtkFieldData* fd = output->GetFieldData();
  fd->PassData(input->GetFieldData());
  for (int k = 0; k < 4; ++k)
  {
    const int kind = static_cast<int>(Kinds[k]);
    const std::string name = KindNames[k];
    AddCount(fd, name + "Count", static_cast<vtkIdType>(stats.cells[kind]));
    AddValue(fd, name + "CountRatio", static_cast<double>(stats.cells[kind]) / nc);
    AddValue(fd, name + "Volume", stats.volume[kind]);
    AddValue(fd, name + "VolumeRatio",
      stats.total_volume > 0 ? stats.volume[kind] / stats.total_volume : 0.0);
  }
  AddValue(fd, "TotalVolume", stats.total_volume);
  AddKindCounts(fd, "CandidateCounts", stats.candidates);
  AddKindCounts(fd, "AdmissibleCandidateCounts", stats.admissible);
  AddCount(fd, "NonConformalInterfaces", static_cast<vtkIdType>(stats.nonconformal_interfaces));
  AddCount(fd, "DissolvedNonConformal", static_cast<vtkIdType>(stats.dissolved_nonconformal));
  AddSummary(fd, "TetToHexTimes",
    { { "Checks", stats.seconds_adjacency }, { "Search", stats.seconds_search },
      { "Adoption", stats.seconds_adopt }, { "Total", stats.seconds_total } });
  return true;
}
