#include "vtkFEMorphSegment.h"

#include "vtkFEMorphHeapReuse.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"

#include <cstdint>
#include <optional>
#include <string>

vtkStandardNewMacro(vtkFEMorphSegment);

//------------------------------------------------------------------------------
vtkFEMorphSegment::vtkFEMorphSegment()
  : vtkFEMorphAlgorithm("FEMorph Segment", Tetrahedra)
{
  const femorph::SegmentationParams defaults;
  this->SharpAngle = defaults.sharp_angle_deg;
  this->CylinderAngleTolerance = defaults.cylinder_angle_tolerance_deg;
  this->ConeAngleTolerance = defaults.cone_angle_tolerance_deg;
  this->SphereDirectionAngle = defaults.sphere_direction_angle_deg;
  this->DistanceTolerance = defaults.distance_tolerance;
  this->RansacIterations = defaults.ransac_iterations;
  this->RandomSeed = static_cast<int>(defaults.random_seed);
  this->RefineFits = defaults.refine_fits ? 1 : 0;
  this->AdaptiveTolerance = defaults.adaptive_tolerance ? 1 : 0;
  this->SetNumberOfOutputPorts(3);
}

vtkFEMorphSegment::~vtkFEMorphSegment() = default;

//------------------------------------------------------------------------------
void vtkFEMorphSegment::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SharpAngle: " << this->SharpAngle << "\n";
  os << indent << "CylinderAngleTolerance: " << this->CylinderAngleTolerance << "\n";
  os << indent << "ConeAngleTolerance: " << this->ConeAngleTolerance << "\n";
  os << indent << "SphereDirectionAngle: " << this->SphereDirectionAngle << "\n";
  os << indent << "DistanceTolerance: " << this->DistanceTolerance << "\n";
  os << indent << "RansacIterations: " << this->RansacIterations << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "RefineFits: " << (this->RefineFits ? "On" : "Off") << "\n";
  os << indent << "AdaptiveTolerance: " << (this->AdaptiveTolerance ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* vtkFEMorphSegment::GetMeshOutput()
{
  return vtkUnstructuredGrid::SafeDownCast(this->GetOutputDataObject(0));
}

vtkPolyData* vtkFEMorphSegment::GetSurfaceOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutputDataObject(1));
}

vtkTable* vtkFEMorphSegment::GetRegionTableOutput()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(2));
}

//------------------------------------------------------------------------------
int vtkFEMorphSegment::FillOutputPortInformation(int port, vtkInformation* info)
{
  switch (port)
  {
    case 0: info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkUnstructuredGrid"); return 1;
    case 1: info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData"); return 1;
    case 2: info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable"); return 1;
    default: return 0;
  }
}

//------------------------------------------------------------------------------
bool vtkFEMorphSegment::CheckProperties()
{
  if (!(this->CheckRange("SharpAngle", this->SharpAngle, 0, 180, "degrees") &&
        this->CheckRange("CylinderAngleTolerance", this->CylinderAngleTolerance, 0, 90, "degrees") &&
        this->CheckRange("ConeAngleTolerance", this->ConeAngleTolerance, 0, 90, "degrees") &&
        this->CheckRange("SphereDirectionAngle", this->SphereDirectionAngle, 0, 90, "degrees")))
  {
    return false;
  }
  if (!(this->DistanceTolerance > 0 && this->DistanceTolerance <= 1))
  {
    this->Fail("DistanceTolerance must be in (0, 1] (a fraction of the mean edge length); it is " +
      std::to_string(this->DistanceTolerance) + ".");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkFEMorphSegment::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* meshOut = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkPolyData* surfaceOut = vtkPolyData::GetData(outputVector, 1);
  vtkTable* tableOut = vtkTable::GetData(outputVector, 2);

  femorph::SegmentationParams params;
  params.sharp_angle_deg = this->SharpAngle;
  params.cylinder_angle_tolerance_deg = this->CylinderAngleTolerance;
  params.cone_angle_tolerance_deg = this->ConeAngleTolerance;
  params.sphere_direction_angle_deg = this->SphereDirectionAngle;
  params.distance_tolerance = this->DistanceTolerance;
  params.ransac_iterations = this->RansacIterations;
  params.random_seed = static_cast<std::uint64_t>(this->RandomSeed);
  params.refine_fits = this->RefineFits != 0;
  params.adaptive_tolerance = this->AdaptiveTolerance != 0;

  // Freed memory is reused during the run (vtkFEMorphHeapReuse.h) up to the
  // outputs, whose arrays outlive the filter.
  std::optional<vtkFEMorphHeapReuse> heapReuse;
  heapReuse.emplace();

  // The tet mesh: tets only, consistently oriented, manifold boundary.
  // Zero-volume tets are accepted: only the boundary is segmented.
  this->Progress(0.0, "converting the mesh");
  femorph::TetMesh mesh;
  femorph::BuildOptions options;
  options.allow_degenerate = true;
  femorph::BuildReport buildReport;
  if (!this->ToTetMesh(input, options, mesh, &buildReport))
  {
    return false;
  }
  if (buildReport.degenerate_tets > 0)
  {
    this->Warn(Plural(buildReport.degenerate_tets, "tetrahedron has", "tetrahedra have") +
      " zero volume (FEMorph Mesh Quality lists them); the segmentation uses the boundary "
      "surface only. FEMorph Improve accepts the mesh and removes them by local operations "
      "(with Require Valid on, it fails naming those it cannot remove); FEMorph Deform refuses "
      "the mesh until they are removed, so run Improve first.");
  }
  if (!this->Progress(0.05))
  {
    return true;
  }

  femorph::SurfaceMesh surface;
  femorph::Segmentation segmentation;
  const femorph::Status segmented =
    femorph::segment_boundary(mesh, params, surface, segmentation, this->ProgressRange(0.1, 0.9));
  if (this->WasAborted())
  {
    return true;
  }
  if (!this->Check(segmented))
  {
    return false;
  }
  this->WarnAll(segmentation.warnings);

  heapReuse.reset();
  this->Progress(0.9, "writing the outputs");
  meshOut->ShallowCopy(input);
  femorph::Status written =
    vtkFEMorphSegmentationArrays::WriteToMesh(surface, segmentation, meshOut);
  if (written)
  {
    written = vtkFEMorphSegmentationArrays::WriteSurface(surface, segmentation, input, surfaceOut);
  }
  if (written)
  {
    written = vtkFEMorphSegmentationArrays::WriteRegionTable(segmentation, tableOut);
  }
  if (!written)
  {
    this->Fail("internal error, " + written.message + ".");
    return false;
  }
  return true;
}
