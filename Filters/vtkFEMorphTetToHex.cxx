#include "vtkFEMorphTetToHex.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "hex/tet_to_hex.h"

#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphTetToHex);

namespace
{
const char* const Label = "FEMorph Tet To Hex";
constexpr vtkIdType MaxCoreIndex = std::numeric_limits<femorph::index_t>::max();

// Output kinds in Table 4.3's order and their names in the field data.
const femorph::CellKind Kinds[4] = { femorph::CellKind::Hexahedron, femorph::CellKind::Wedge,
  femorph::CellKind::Pyramid, femorph::CellKind::Tetra };
const char* const KindNames[4] = { "Hex", "Prism", "Pyramid", "Tet" };

int CellTypeOf(femorph::CellKind kind)
{
  switch (kind)
  {
    case femorph::CellKind::Hexahedron: return VTK_HEXAHEDRON;
    case femorph::CellKind::Wedge: return VTK_WEDGE;
    case femorph::CellKind::Pyramid: return VTK_PYRAMID;
    case femorph::CellKind::Tetra: break;
  }
  return VTK_TETRA;
}

void AddValue(vtkFieldData* fd, const std::string& name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

void AddCount(vtkFieldData* fd, const std::string& name, vtkIdType value)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

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
int vtkFEMorphTetToHex::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphTetToHex::RequestData(
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
  // The step names shown next to the progress bar end with this request.
  struct ClearProgressText
  {
    vtkAlgorithm* Algorithm;
    ~ClearProgressText() { this->Algorithm->SetProgressText(nullptr); }
  } clearProgressText{ this };

  const vtkIdType numCells = input->GetNumberOfCells();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numCells == 0)
  {
    output->ShallowCopy(input);
    return 1;
  }
  // The clamp macros let NaN through.
  if (!std::isfinite(this->QuadAngle) || !std::isfinite(this->MinScaledJacobian))
  {
    vtkErrorMacro(<< Label << ": QuadAngle (" << this->QuadAngle << ") and MinScaledJacobian ("
                  << this->MinScaledJacobian << ") must be numbers.");
    return 0;
  }
  std::string others;
  if (vtkFEMorphMeshConversion::DescribeOtherCells(input, VTK_TETRA, others) > 0)
  {
    vtkErrorMacro(<< Label << " accepts tetrahedra only; the input has " << others
                  << " (ParaView's Tetrahedralize filter converts them).");
    return 0;
  }
  if (numPoints > MaxCoreIndex || numCells > MaxCoreIndex / 4)
  {
    vtkErrorMacro(<< Label << ": the input is too large (" << numPoints << " points, " << numCells
                  << " cells; the limit is " << MaxCoreIndex / 4 << ").");
    return 0;
  }
  if (const vtkIdType bad = vtkFEMorphMeshConversion::CountNonFinitePoints(input->GetPoints()))
  {
    vtkErrorMacro(<< Label << ": " << bad << (bad == 1 ? " point has" : " points have")
                  << " NaN or infinite coordinates. Fix or remove these points first.");
    return 0;
  }

  this->SetProgressText("converting the mesh");
  this->UpdateProgress(0.0);
  femorph::TetToHexResult result;
  bool aborted = false;
  try
  {
    std::vector<femorph::Vec3> points(static_cast<std::size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      input->GetPoint(i, points[i].data());
    }
    std::vector<femorph::Tet> tets(static_cast<std::size_t>(numCells));
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      vtkIdType npts = 0;
      const vtkIdType* pts = nullptr;
      input->GetCellPoints(c, npts, pts);
      if (npts != 4)
      {
        vtkErrorMacro(<< Label << ": cell " << c << " is a VTK_TETRA with " << npts
                      << " points; the input is corrupt.");
        return 0;
      }
      for (int k = 0; k < 4; ++k)
      {
        if (pts[k] < 0 || pts[k] >= numPoints)
        {
          vtkErrorMacro(<< Label << ": cell " << c << " refers to point " << pts[k]
                        << " but the input has " << numPoints << " points; the input is corrupt.");
          return 0;
        }
        tets[c][k] = static_cast<femorph::index_t>(pts[k]);
      }
    }

    femorph::TetToHexParams params;
    params.quad_angle_deg = this->QuadAngle;
    params.min_scaled_jacobian = this->MinScaledJacobian;
    params.hexahedra = this->Hexahedra != 0;
    params.prisms = this->Prisms != 0;
    params.pyramids = this->Pyramids != 0;
    params.refuse_nonconformal = this->RefuseNonConformal != 0;
    params.progress = [this, &aborted](double fraction, const char* step) {
      this->SetProgressText(step);
      this->UpdateProgress(0.05 + 0.9 * fraction);
      aborted = aborted || this->CheckAbort();
      return !aborted;
    };
    const femorph::Status status = femorph::recombine_tetrahedra(points, tets, params, result);
    if (aborted)
    {
      return 1;
    }
    if (!status)
    {
      vtkErrorMacro(<< Label << ": " << status.message
                    << " (cell ids are the input's; FEMorph Mesh Quality shows inverted and flat "
                       "tetrahedra).");
      return 0;
    }
  }
  catch (const std::bad_alloc&)
  {
    vtkErrorMacro(<< Label << ": out of memory.");
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< Label << " failed: " << e.what());
    return 0;
  }

  this->SetProgressText("writing the output");
  const femorph::MixedCells& cells = result.cells;
  const vtkIdType nc = cells.size();
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nc + 1);
  for (vtkIdType c = 0; c <= nc; ++c)
  {
    offsets->SetValue(c, cells.offsets[c]);
  }
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(cells.connectivity.size()));
  for (std::size_t i = 0; i < cells.connectivity.size(); ++i)
  {
    connectivity->SetValue(static_cast<vtkIdType>(i), cells.connectivity[i]);
  }
  vtkNew<vtkCellArray> cellArray;
  cellArray->SetData(offsets, connectivity);
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfTuples(nc);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    types->SetValue(c, static_cast<unsigned char>(CellTypeOf(cells.kinds[c])));
  }
  output->SetPoints(input->GetPoints());
  output->SetCells(types, cellArray);
  output->GetPointData()->PassData(input->GetPointData());

  // Cell data: each cell takes its first source tet's values.
  vtkCellData* outCD = output->GetCellData();
  vtkNew<vtkIdList> from, to;
  from->SetNumberOfIds(nc);
  to->SetNumberOfIds(nc);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    from->SetId(c, result.source_tets[result.source_offsets[c]]);
    to->SetId(c, c);
  }
  outCD->CopyAllocate(input->GetCellData(), nc);
  outCD->CopyData(input->GetCellData(), from, to);
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
  vtkNew<vtkDoubleArray> times;
  times->SetName("TetToHexTimes");
  times->SetNumberOfComponents(4);
  times->SetNumberOfTuples(1);
  const char* timeNames[4] = { "Checks", "Search", "Adoption", "Total" };
  const double timeValues[4] = { stats.seconds_adjacency, stats.seconds_search,
    stats.seconds_adopt, stats.seconds_total };
  for (int k = 0; k < 4; ++k)
  {
    times->SetComponentName(k, timeNames[k]);
    times->SetTypedComponent(0, k, timeValues[k]);
  }
  fd->AddArray(times);
  this->UpdateProgress(1.0);
  return 1;
}
