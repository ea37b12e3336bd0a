#include "vtkFEMorphSegment.h"

#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <new>
#include <string>
#include <utility>

vtkStandardNewMacro(vtkFEMorphSegment);

namespace
{
const char* const Label = "FEMorph Segment";

// Progress: the share of each stage in [0, 1].
constexpr double ConvertedProgress = 0.05; // tet mesh built
constexpr double SurfaceProgress = 0.1;    // boundary surface extracted
constexpr double SegmentedProgress = 0.9;  // segment_surface done; then the outputs

std::string Plural(std::size_t n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}
}

//------------------------------------------------------------------------------
vtkFEMorphSegment::vtkFEMorphSegment()
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
int vtkFEMorphSegment::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
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
int vtkFEMorphSegment::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* meshOut = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkPolyData* surfaceOut = vtkPolyData::GetData(outputVector, 1);
  vtkTable* tableOut = vtkTable::GetData(outputVector, 2);
  if (!input || !meshOut || !surfaceOut || !tableOut)
  {
    vtkErrorMacro(<< Label << " needs a vtkUnstructuredGrid input.");
    return 0;
  }
  meshOut->Initialize();
  surfaceOut->Initialize();
  tableOut->Initialize();
  // The step names shown next to the progress bar end with this request.
  struct ClearProgressText
  {
    vtkAlgorithm* Algorithm;
    ~ClearProgressText() { this->Algorithm->SetProgressText(nullptr); }
  } clearProgressText{ this };

  if (input->GetNumberOfCells() == 0)
  {
    meshOut->ShallowCopy(input);
    return 1;
  }

  // The clamp macros let NaN through.
  const std::pair<const char*, double> angles[] = { { "SharpAngle", this->SharpAngle },
    { "CylinderAngleTolerance", this->CylinderAngleTolerance },
    { "ConeAngleTolerance", this->ConeAngleTolerance },
    { "SphereDirectionAngle", this->SphereDirectionAngle } };
  for (const auto& angle : angles)
  {
    if (!std::isfinite(angle.second))
    {
      vtkErrorMacro(<< Label << ": " << angle.first << " must be an angle in degrees; it is "
                    << angle.second << ".");
      return 0;
    }
  }
  if (!(this->DistanceTolerance > 0 && this->DistanceTolerance <= 1))
  {
    vtkErrorMacro(<< Label << ": DistanceTolerance must be in (0, 1] (a fraction of the mean "
                  << "edge length); it is " << this->DistanceTolerance << ".");
    return 0;
  }

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

  bool aborted = false;
  femorph::SurfaceMesh surface;
  femorph::Segmentation segmentation;
  try
  {
    // The tet mesh: tets only, consistently oriented, manifold boundary.
    // Zero-volume tets are accepted: only the boundary is segmented.
    this->SetProgressText("converting the mesh");
    this->UpdateProgress(0.0);
    femorph::TetMesh mesh;
    femorph::BuildOptions options;
    options.allow_degenerate = true;
    femorph::BuildReport buildReport;
    const femorph::Status converted =
      vtkFEMorphMeshConversion::ToTetMesh(input, Label, options, mesh, &buildReport);
    if (!converted)
    {
      vtkErrorMacro(<< converted.message);
      return 0;
    }
    if (buildReport.unused_points > 0)
    {
      vtkWarningMacro(<< Label << ": "
                      << Plural(buildReport.unused_points, "point is", "points are")
                      << " not used by any tetrahedron; "
                      << (buildReport.unused_points == 1 ? "it gets" : "they get")
                      << " VertexClass 0.");
    }
    if (buildReport.degenerate_tets > 0)
    {
      vtkWarningMacro(<< Label << ": "
                      << Plural(buildReport.degenerate_tets, "tetrahedron has", "tetrahedra have")
                      << " zero volume (FEMorph Mesh Quality lists them); the segmentation "
                         "uses the boundary surface only, but Deform and Improve will refuse "
                         "the mesh.");
    }
    this->UpdateProgress(ConvertedProgress);
    if (this->CheckAbort())
    {
      meshOut->Initialize();
      return 1;
    }

    this->SetProgressText("extracting the boundary surface");
    femorph::SurfaceReport surfaceReport;
    const femorph::Status extracted =
      femorph::extract_boundary_surface(mesh, surface, &surfaceReport);
    if (!extracted)
    {
      vtkErrorMacro(<< Label << ": the boundary surface cannot be segmented: "
                    << extracted.message << " (open edges: " << surfaceReport.open_edges
                    << ", non-manifold edges: " << surfaceReport.nonmanifold_edges
                    << ", inconsistently oriented edges: " << surfaceReport.misoriented_edges
                    << ").");
      return 0;
    }
    if (surfaceReport.degenerate_triangles > 0)
    {
      vtkWarningMacro(<< Label << ": "
                      << Plural(surfaceReport.degenerate_triangles,
                           "boundary triangle is", "boundary triangles are")
                      << " degenerate (zero area); "
                      << (surfaceReport.degenerate_triangles == 1 ? "it has" : "they have")
                      << " no normal and may be left in unknown regions.");
    }
    this->UpdateProgress(SurfaceProgress);
    if (this->CheckAbort())
    {
      return 1;
    }

    auto progress = [this, &aborted](double fraction, const char* step) {
      this->SetProgressText(step);
      this->UpdateProgress(
        SurfaceProgress + (SegmentedProgress - SurfaceProgress) * std::min(std::max(fraction, 0.0), 1.0));
      aborted = aborted || this->CheckAbort();
      return !aborted;
    };
    const femorph::Status segmented =
      femorph::segment_surface(surface, params, segmentation, progress);
    if (aborted)
    {
      return 1;
    }
    if (!segmented)
    {
      vtkErrorMacro(<< Label << ": the segmentation failed: " << segmented.message);
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
  for (const std::string& warning : segmentation.warnings)
  {
    vtkWarningMacro(<< Label << ": " << warning);
  }

  this->SetProgressText("writing the outputs");
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
    meshOut->Initialize();
    surfaceOut->Initialize();
    tableOut->Initialize();
    vtkErrorMacro(<< Label << ": internal error, " << written.message << ".");
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}
