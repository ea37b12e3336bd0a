#include "vtkFEMorphImprove.h"

#include "vtkFEMorphHeapReuse.h"
#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "improve/boundary_geometry.h"
#include "improve/improve_target.h"
#include "improve/phased_odt.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"
#include "segment/segmentation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphImprove);

namespace
{
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Where the first few of `tets` are: their centres, for a message.
std::string Centres(const femorph::TetMesh& mesh, const std::vector<femorph::index_t>& tets)
{
  std::ostringstream where;
  const std::size_t shown = std::min<std::size_t>(tets.size(), 5);
  for (std::size_t i = 0; i < shown; ++i)
  {
    const femorph::Tet& T = mesh.tet(tets[i]);
    const femorph::Vec3 c =
      (mesh.point(T[0]) + mesh.point(T[1]) + mesh.point(T[2]) + mesh.point(T[3])) / 4;
    where << (i ? "; " : "") << "(" << c.x() << ", " << c.y() << ", " << c.z() << ")";
  }
  return where.str() + (tets.size() > shown ? "; ..." : "");
}

/// Cell arrays Stretch (Eq. 1.1) and Inverted (negative volume) of the output.
void AddQualityArrays(const femorph::CompactMesh& compact, vtkUnstructuredGrid* output)
{
  const vtkIdType numTets = static_cast<vtkIdType>(compact.tets.size());
  std::vector<double> stretch(compact.tets.size()), volume(compact.tets.size());
  femorph::compute_tet_quality(
    compact.points, compact.tets, stretch.data(), nullptr, nullptr, nullptr, volume.data());
  vtkNew<vtkDoubleArray> stretchArray;
  stretchArray->SetName("Stretch");
  stretchArray->SetNumberOfTuples(numTets);
  vtkNew<vtkUnsignedCharArray> inverted;
  inverted->SetName("Inverted");
  inverted->SetNumberOfTuples(numTets);
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    stretchArray->SetValue(t, stretch[static_cast<std::size_t>(t)]);
    inverted->SetValue(t, volume[static_cast<std::size_t>(t)] < 0 ? 1 : 0);
  }
  output->GetCellData()->AddArray(stretchArray);
  output->GetCellData()->AddArray(inverted);
  output->GetCellData()->SetActiveScalars("Stretch");
}

/// Seconds spent outside phased_odt (which times its own steps).
struct ImproveTimes
{
  double Segmentation = 0, Preparation = 0, Output = 0, Total = 0;
};

/// The field-data summary: ImproveStretch, ImproveDensityError (NaN without
/// a density target), ImproveCounts, ImproveTimes, ImproveStepTimes and,
/// with `trace`, ImproveQualityTrace.
void AddImproveSummary(vtkFieldData* fd, const femorph::PhasedOdtStats& stats, bool density,
  const ImproveTimes& times, bool trace)
{
  using Filter = vtkFEMorphAlgorithm;
  Filter::AddSummary(fd, "ImproveStretch",
    { { "MinBefore", stats.min_stretch_before }, { "MeanBefore", stats.mean_stretch_before },
      { "MinAfter", stats.min_stretch_after }, { "MeanAfter", stats.mean_stretch_after } });
  Filter::AddSummary(fd, "ImproveDensityError",
    { { "Before", density ? stats.density_error_before.mean : NaN },
      { "After", density ? stats.density_error_after.mean : NaN } });
  const auto d = [](std::size_t n) { return static_cast<double>(n); };
  Filter::AddSummary(fd, "ImproveCounts",
    { { "Splits", d(stats.splits) }, { "Collapses", d(stats.collapses) },
      { "AccuracySplits", d(stats.accuracy_splits) }, { "Flips23", d(stats.flips_23) },
      { "Flips32", d(stats.flips_32) }, { "Flips44", d(stats.flips_44) },
      { "SurfaceFlips", d(stats.surface_flips) }, { "RemovedSlivers", d(stats.removed_slivers) },
      { "RemovedCaps", d(stats.removed_caps) }, { "RemovedSpades", d(stats.removed_spades) },
      { "RepairedInverted", d(stats.removed_inverted) },
      { "RemainingInverted", d(stats.remaining_inverted.size()) },
      { "MovedVertices", d(stats.moved_vertices) }, { "BelowFloor", d(stats.below_floor) },
      { "BelowFloorAllBoundary", d(stats.below_floor_on_boundary) },
      { "TetsBefore", d(stats.tets_before) }, { "TetsAfter", d(stats.tets_after) },
      { "LeftAsItWas", stats.skipped ? 1.0 : 0.0 }, { "KeptInput", stats.kept_input ? 1.0 : 0.0 } });
  Filter::AddSummary(fd, "ImproveTimes",
    { { "Segmentation", times.Segmentation }, { "Curves", stats.phase_seconds[0] },
      { "Surfaces", stats.phase_seconds[1] }, { "Volume", stats.phase_seconds[2] },
      { "Total", times.Total } });
  // The same time by step: set-up, the steps of Fig. 2.34 over all phases,
  // the output.
  std::vector<std::pair<std::string, double>> steps{ { "Preparation", times.Preparation } };
  for (std::size_t i = 0; i < stats.step_seconds.size(); ++i)
  {
    steps.emplace_back(femorph::PhasedOdtStats::kStepNames[i], stats.step_seconds[i]);
  }
  steps.emplace_back("Output", times.Output);
  Filter::AddSummary(fd, "ImproveStepTimes", steps);
  if (trace)
  {
    // Seconds from the filter's start: the set-up before the loop first.
    vtkNew<vtkDoubleArray> array;
    array->SetName("ImproveQualityTrace");
    array->SetNumberOfComponents(2);
    array->SetComponentName(0, "Seconds");
    array->SetComponentName(1, "MinStretch");
    for (const auto& point : stats.quality_trace)
    {
      const double tuple[2] = { times.Segmentation + times.Preparation + point[0], point[1] };
      array->InsertNextTuple(tuple);
    }
    fd->AddArray(array);
  }
}
}

//------------------------------------------------------------------------------
vtkFEMorphImprove::vtkFEMorphImprove()
  : vtkFEMorphAlgorithm("FEMorph Improve", Tetrahedra)
{
  this->SetNumberOfInputPorts(2);
  const femorph::PhasedOdtOptions defaults;
  this->PoorElementsOnly = defaults.poor_elements_only;
  this->SmoothCurves = defaults.smooth_curves;
  this->SmoothSurfaces = defaults.smooth_surfaces;
  this->SmoothVolume = defaults.smooth_volume;
  this->RemoveDegenerate = defaults.remove_degenerate;
  this->RemoveInverted = defaults.remove_inverted;
  this->DensityControl = defaults.density_control;
  this->AccuracyControl = defaults.accuracy_control;
  this->Flips = defaults.flips;
  this->RelaxEdgeLengths = defaults.relax_edge_lengths;
  this->MoveUnfittedRegions = defaults.move_unfitted_regions;
  this->OdtIterations = defaults.odt_iterations;
  this->MaxLoops = defaults.max_loops;
  this->SplitThreshold = defaults.split_threshold;
  this->CollapseThreshold = defaults.collapse_threshold;
  this->DegenerateThreshold = defaults.degenerate_threshold;
  this->QualityFloor = defaults.quality_floor;
  this->TraceQuality = defaults.trace_quality;
  this->GridCellSize = femorph::ImproveTargetOptions().grid_cell_size;
}

vtkFEMorphImprove::~vtkFEMorphImprove() = default;

//------------------------------------------------------------------------------
void vtkFEMorphImprove::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PoorElementsOnly: " << this->PoorElementsOnly << "\n";
  os << indent << "SmoothCurves: " << this->SmoothCurves << "\n";
  os << indent << "SmoothSurfaces: " << this->SmoothSurfaces << "\n";
  os << indent << "SmoothVolume: " << this->SmoothVolume << "\n";
  os << indent << "RemoveDegenerate: " << this->RemoveDegenerate << "\n";
  os << indent << "RemoveInverted: " << this->RemoveInverted << "\n";
  os << indent << "DensityControl: " << this->DensityControl << "\n";
  os << indent << "AccuracyControl: " << this->AccuracyControl << "\n";
  os << indent << "Flips: " << this->Flips << "\n";
  os << indent << "RelaxEdgeLengths: " << this->RelaxEdgeLengths << "\n";
  os << indent << "MoveUnfittedRegions: " << this->MoveUnfittedRegions << "\n";
  os << indent << "OdtIterations: " << this->OdtIterations << "\n";
  os << indent << "MaxLoops: " << this->MaxLoops << "\n";
  os << indent << "SplitThreshold: " << this->SplitThreshold << "\n";
  os << indent << "CollapseThreshold: " << this->CollapseThreshold << "\n";
  os << indent << "GridCellSize: " << this->GridCellSize << "\n";
  os << indent << "DegenerateThreshold: " << this->DegenerateThreshold << "\n";
  os << indent << "QualityFloor: " << this->QualityFloor << "\n";
  os << indent << "RegionArrayName: " << this->RegionArrayName << "\n";
  os << indent << "SegmentIfMissing: " << this->SegmentIfMissing << "\n";
  os << indent << "RequireValid: " << this->RequireValid << "\n";
  os << indent << "TraceQuality: " << this->TraceQuality << "\n";
}

//------------------------------------------------------------------------------
std::string vtkFEMorphImprove::GetInputName(int port)
{
  return port == 1 ? "the Reference input" : this->Superclass::GetInputName(port);
}

//------------------------------------------------------------------------------
bool vtkFEMorphImprove::CheckProperties()
{
  if (!(this->CheckRange("SplitThreshold", this->SplitThreshold, 1, 100) &&
        this->CheckRange("CollapseThreshold", this->CollapseThreshold, 0, 1) &&
        this->CheckRange("GridCellSize", this->GridCellSize, 0, 1e30) &&
        this->CheckRange("DegenerateThreshold", this->DegenerateThreshold, 0, 0.5) &&
        this->CheckRange("QualityFloor", this->QualityFloor, 0.05, 0.6)))
  {
    return false;
  }
  const double beta1 = this->SplitThreshold, beta2 = this->CollapseThreshold;
  if (!(beta1 > 0 && beta2 > 0 && beta1 > 2 * beta2 && 1 + beta2 / 2 < beta1))
  {
    std::ostringstream os;
    os << "the density thresholds SplitThreshold = " << beta1 << " and CollapseThreshold = " << beta2
       << " do not converge; thesis 2.6.3 needs SplitThreshold > 2 x CollapseThreshold and 1 + "
          "CollapseThreshold / 2 < SplitThreshold (defaults 1.5 and 0.67).";
    this->Fail(os.str());
    return false;
  }
  if (!(this->QualityFloor > this->DegenerateThreshold))
  {
    std::ostringstream os;
    os << "QualityFloor = " << this->QualityFloor << " must be above DegenerateThreshold = "
       << this->DegenerateThreshold
       << " (the stretch below which tetrahedra are removed; defaults 0.3 and 0.05).";
    this->Fail(os.str());
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkFEMorphImprove::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* reference = vtkUnstructuredGrid::GetData(inputVector[1], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  const auto start = Clock::now();

  // The region restriction.
  std::vector<std::uint8_t> tetMask;
  if (!this->RegionArrayName.empty())
  {
    if (!this->Check(vtkFEMorphMeshConversion::ReadCellMask(
          input, this->RegionArrayName, "RegionArrayName", tetMask)))
    {
      return false;
    }
    if (std::find(tetMask.begin(), tetMask.end(), 1) == tetMask.end())
    {
      this->Warn("no cell has a nonzero '" + this->RegionArrayName +
        "'; the mesh is passed through unchanged.");
      output->ShallowCopy(input);
      return true;
    }
  }

  // Freed memory is reused during the run (vtkFEMorphHeapReuse.h), up to
  // the output, whose arrays outlive the filter.
  std::optional<vtkFEMorphHeapReuse> heapReuse;
  heapReuse.emplace();

  // The segmentation from the arrays; a grid that carries them must carry
  // them whole and valid.
  vtkSmartPointer<vtkUnstructuredGrid> working = input;
  vtkFEMorphSegmentationArrays::MeshSegmentation seg;
  bool haveSegmentation = vtkFEMorphSegmentationArrays::HasSegmentation(input);
  if (haveSegmentation && !this->Check(vtkFEMorphSegmentationArrays::ReadFromMesh(input, seg)))
  {
    return false;
  }

  // The mesh, read once; inverted tets are what Improve repairs.
  this->Progress(0.0, "converting the mesh");
  femorph::TetMesh mesh;
  femorph::BuildOptions options;
  options.allow_inverted = true;
  options.allow_degenerate = true;
  options.face_regions = seg.FaceRegions;
  if (!this->ToTetMesh(input, options, mesh))
  {
    return false;
  }

  double segmentationSeconds = 0;
  if (!haveSegmentation && this->SegmentIfMissing)
  {
    const auto t0 = Clock::now();
    std::size_t regionCount = 0;
    const femorph::Status segmented = vtkFEMorphSegmentationArrays::SegmentMesh(
      mesh, input, working, seg, regionCount, this->ProgressRange(0.0, 0.05));
    if (this->WasAborted())
    {
      return true;
    }
    if (!segmented)
    {
      this->Fail("the input has no segmentation arrays and segmenting it failed: " +
        segmented.message);
      return false;
    }
    this->Warn("the input has no segmentation arrays (run FEMorph Segment first to choose its "
               "settings); it was segmented with the default settings into " +
      std::to_string(regionCount) + " regions.");
    haveSegmentation = true;
    segmentationSeconds = SecondsSince(t0);
  }
  else if (!haveSegmentation)
  {
    this->Warn("the input has no segmentation arrays and SegmentIfMissing is off: every boundary "
               "vertex is kept where it is.");
  }
  if (!this->Progress(0.05))
  {
    return true;
  }
  femorph::BoundaryGeometry geometry;
  if (haveSegmentation)
  {
    geometry = femorph::make_boundary_geometry(seg.RegionSurfaces, seg.Curves);
  }

  // The target: density field and acceptable geometric error, from the
  // Reference when there is one.
  femorph::ReferenceMesh referenceMesh;
  const bool useReference = reference && reference->GetNumberOfCells() > 0;
  if (useReference)
  {
    if (!this->Check(vtkFEMorphMeshConversion::ReadTetGrid(
          reference, referenceMesh.points, referenceMesh.tets)))
    {
      return false;
    }
    const femorph::Status valid = femorph::check_reference_mesh(referenceMesh);
    if (!valid)
    {
      this->Fail("the Reference input is not a valid mesh: " + valid.message + ".");
      return false;
    }
    vtkFEMorphSegmentationArrays::MeshSegmentation refSeg;
    if (haveSegmentation && vtkFEMorphSegmentationArrays::HasSegmentation(reference))
    {
      if (!this->Check(vtkFEMorphSegmentationArrays::ReadFromMesh(
            reference, refSeg, this->GetInputName(1))))
      {
        return false;
      }
      referenceMesh.face_regions = std::move(refSeg.FaceRegions);
      referenceMesh.region_types = refSeg.RegionTypes;
      referenceMesh.geometry = femorph::make_boundary_geometry(refSeg.RegionSurfaces, refSeg.Curves);
    }
  }
  femorph::ImproveTargetOptions targetOptions;
  // Repairing the poor elements only needs no density target.
  targetOptions.density = !this->PoorElementsOnly;
  targetOptions.grid_cell_size = this->GridCellSize;
  const femorph::ImproveTarget target = femorph::make_improve_target(mesh,
    haveSegmentation ? &geometry : nullptr, useReference ? &referenceMesh : nullptr, targetOptions);
  this->WarnAll(target.warnings);
  referenceMesh = femorph::ReferenceMesh();

  femorph::PhasedOdtOptions po;
  po.smooth_curves = this->SmoothCurves != 0;
  po.smooth_surfaces = this->SmoothSurfaces != 0;
  po.smooth_volume = this->SmoothVolume != 0;
  po.remove_degenerate = this->RemoveDegenerate != 0;
  po.remove_inverted = this->RemoveInverted != 0;
  po.density_control = this->DensityControl != 0;
  po.accuracy_control = this->AccuracyControl != 0;
  po.flips = this->Flips != 0;
  po.relax_edge_lengths = this->RelaxEdgeLengths != 0;
  po.move_unfitted_regions = this->MoveUnfittedRegions != 0;
  po.odt_iterations = this->OdtIterations;
  po.max_loops = this->MaxLoops;
  po.split_threshold = this->SplitThreshold;
  po.collapse_threshold = this->CollapseThreshold;
  po.degenerate_threshold = this->DegenerateThreshold;
  po.quality_floor = this->QualityFloor;
  po.tet_mask = std::move(tetMask);
  po.fix_boundary = !haveSegmentation;
  po.trace_quality = this->TraceQuality != 0;
  po.poor_elements_only = this->PoorElementsOnly != 0;
  // Without a Reference the density target is the input's own: a mesh at
  // its own density must not come out with a lower minimum.
  po.keep_input_minimum = !useReference;
  po.progress = this->ProgressRange(0.05, 0.95);
  const double preparationSeconds = SecondsSince(start) - segmentationSeconds;
  const femorph::PhasedOdtStats stats = femorph::phased_odt(mesh, geometry, target.view(), po);
  const auto improveEnd = Clock::now();
  if (this->WasAborted())
  {
    return true;
  }

  if (stats.kept_input)
  {
    std::ostringstream os;
    os << "the mesh is output unchanged: the improvement would have lowered the minimum stretch from "
       << std::round(1000 * stats.min_stretch_before) / 1000 << " to "
       << std::round(1000 * stats.min_stretch_rejected) / 1000 << ", below "
       << (useReference ? "the input's minimum or Quality Floor, whichever is lower"
                        : "the input's minimum (without a Reference the target density is the input's own, "
                          "so a lower minimum buys nothing)")
       << ". KeptInput is 1 in ImproveCounts.";
    this->Warn(os.str());
  }

  // Inverted tets no operation could repair.
  const std::size_t remaining = stats.remaining_inverted.size();
  if (remaining > 0 && this->RequireValid)
  {
    this->Fail(Plural(remaining, "inverted tetrahedron", "inverted tetrahedra") +
      " could not be repaired by local operations (centres " +
      Centres(mesh, stats.remaining_inverted) +
      "). Turn RequireValid off to get the mesh with them marked in the 'Inverted' cell array.");
    return false;
  }
  // Zero-volume tets no operation could remove (a flat input): the output
  // would be no valid mesh. Only a zero minimum stretch can mean one.
  std::vector<femorph::index_t> flat;
  for (femorph::index_t t = 0; !(stats.min_stretch_after > 0) && t < mesh.tet_slots(); ++t)
  {
    if (mesh.tet_alive(t) && mesh.orientation(t) == 0)
    {
      flat.push_back(t);
    }
  }
  if (!flat.empty())
  {
    const std::string what = Plural(flat.size(), "tetrahedron has", "tetrahedra have") +
      " zero volume and could not be removed (centres " + Centres(mesh, flat) +
      "): the input is flat there";
    if (this->RequireValid)
    {
      this->Fail(what + ". Turn RequireValid off to get the mesh with them (Stretch 0).");
      return false;
    }
    this->Warn(what + "; they have Stretch 0.");
  }

  this->Progress(0.95, "writing the output");
  const femorph::CompactMesh compact = mesh.compact();
  heapReuse.reset();
  this->FromCompactMesh(compact, working, output);
  AddQualityArrays(compact, output);
  if (remaining > 0)
  {
    this->Warn(Plural(remaining, "inverted tetrahedron", "inverted tetrahedra") +
      " could not be repaired; they have Inverted = 1.");
  }
  // What limits the quality when the floor is not reached everywhere and
  // the boundary is the cause.
  if (stats.below_floor_on_boundary > 0)
  {
    std::ostringstream os;
    os << Plural(stats.below_floor, "tetrahedron stays", "tetrahedra stay") << " below stretch "
       << po.quality_floor << " (minimum " << std::round(1000 * stats.min_stretch_after) / 1000
       << "); " << stats.below_floor_on_boundary
       << " of them have all four vertices on the boundary, so their shape is that of the "
          "boundary triangles (typically a face much narrower than the mesh, such as a strip "
          "between two curves). Only a finer surface mesh there would help; see the Stretch cell "
          "array.";
    this->Warn(os.str());
  }

  vtkFieldData* fd = output->GetFieldData();
  if (haveSegmentation && !seg.Curves.empty())
  {
    vtkFEMorphSegmentationArrays::WriteTracedCurves(compact, seg.Curves, geometry.curve_regions, fd);
  }

  ImproveTimes times;
  times.Segmentation = segmentationSeconds;
  times.Preparation = preparationSeconds;
  times.Output = SecondsSince(improveEnd);
  times.Total = SecondsSince(start);
  AddImproveSummary(fd, stats, !target.density.empty() && po.density_control, times,
    this->TraceQuality != 0);
  if (haveSegmentation)
  {
    AddValues(fd, "GeometricError", stats.geometric_error_after);
    std::vector<double> targetError(geometry.regions.size(), NaN);
    for (std::size_t r = 0; r < targetError.size() && r < target.acceptable_error.size(); ++r)
    {
      targetError[r] = target.acceptable_error[r];
    }
    AddValues(fd, "AcceptableGeometricError", targetError);
  }
  return true;
}
