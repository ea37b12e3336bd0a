#include "vtkFEMorphImprove.h"

#include "vtkFEMorphHeapReuse.h"
#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "improve/boundary_geometry.h"
#include "improve/control_shape_accuracy.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "mesh/trace_boundary_curves.h"
#include "quality/tet_quality.h"
#include "segment/segmentation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphImprove);

namespace
{
const char* const Label = "FEMorph Improve";
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// One-tuple double array with named components.
void AddSummary(vtkFieldData* fd, const char* name, const std::vector<std::pair<const char*, double>>& values)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(static_cast<int>(values.size()));
  a->SetNumberOfTuples(1);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    a->SetComponentName(static_cast<vtkIdType>(i), values[i].first);
    a->SetComponent(0, static_cast<int>(i), values[i].second);
  }
  fd->AddArray(a);
}

void AddPerRegion(vtkFieldData* fd, const char* name, const std::vector<double>& values)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    a->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  fd->AddArray(a);
}

/// The fitted surfaces and curves of a segmentation read from the arrays.
femorph::BoundaryGeometry MakeGeometry(const vtkFEMorphSegmentationArrays::MeshSegmentation& seg)
{
  femorph::BoundaryGeometry g;
  g.regions = seg.RegionSurfaces;
  for (std::size_t r = 0; r < g.regions.size() && r < seg.RegionTypes.size(); ++r)
  {
    g.regions[r].type = seg.RegionTypes[r];
  }
  for (std::size_t c = 0; c < seg.CurveTypes.size(); ++c)
  {
    const double* p = seg.CurveParameters[c].data();
    femorph::CurvePrimitive curve;
    curve.type = seg.CurveTypes[c];
    curve.center = femorph::Vec3(p[0], p[1], p[2]);
    curve.normal = femorph::Vec3(p[3], p[4], p[5]);
    curve.direction = femorph::Vec3(p[6], p[7], p[8]);
    curve.radius = p[9];
    curve.minor_radius = p[10];
    curve.start = femorph::Vec3(p[11], p[12], p[13]);
    curve.end = femorph::Vec3(p[14], p[15], p[16]);
    g.curves.push_back(curve);
    g.curve_regions.push_back({ static_cast<femorph::index_t>(std::lround(p[17])),
      static_cast<femorph::index_t>(std::lround(p[18])) });
  }
  return g;
}

/// Same connectivity: same point count and the same tets in the same order.
bool SameConnectivity(vtkUnstructuredGrid* a, vtkUnstructuredGrid* b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints() || a->GetNumberOfCells() != b->GetNumberOfCells())
  {
    return false;
  }
  vtkIdType na = 0, nb = 0;
  const vtkIdType* pa = nullptr;
  const vtkIdType* pb = nullptr;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    a->GetCellPoints(c, na, pa);
    b->GetCellPoints(c, nb, pb);
    if (na != nb || !std::equal(pa, pa + na, pb))
    {
      return false;
    }
  }
  return true;
}

/// Points and tets of a tetrahedral grid (checked to hold tets only).
void GridArrays(vtkUnstructuredGrid* grid, std::vector<femorph::Vec3>& points, std::vector<femorph::Tet>& tets)
{
  points.resize(static_cast<std::size_t>(grid->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    grid->GetPoint(i, points[static_cast<std::size_t>(i)].data());
  }
  tets.resize(static_cast<std::size_t>(grid->GetNumberOfCells()));
  vtkIdType n = 0;
  const vtkIdType* p = nullptr;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, n, p);
    for (int k = 0; k < 4; ++k)
    {
      tets[static_cast<std::size_t>(c)][k] = static_cast<femorph::index_t>(p[k]);
    }
  }
}
}

//------------------------------------------------------------------------------
vtkFEMorphImprove::vtkFEMorphImprove()
{
  this->SetNumberOfInputPorts(2);
}

vtkFEMorphImprove::~vtkFEMorphImprove() = default;

//------------------------------------------------------------------------------
void vtkFEMorphImprove::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
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
  os << indent << "PoorElementsOnly: " << this->PoorElementsOnly << "\n";
}

//------------------------------------------------------------------------------
int vtkFEMorphImprove::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphImprove::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* reference = vtkUnstructuredGrid::GetData(inputVector[1], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro(<< Label << " needs a vtkUnstructuredGrid input.");
    return 0;
  }
  output->Initialize();
  struct ClearProgressText
  {
    vtkAlgorithm* Algorithm;
    ~ClearProgressText() { this->Algorithm->SetProgressText(nullptr); }
  } clearProgressText{ this };

  if (input->GetNumberOfCells() == 0)
  {
    output->ShallowCopy(input);
    return 1;
  }
  const double beta1 = this->SplitThreshold, beta2 = this->CollapseThreshold;
  if (!(beta1 > 0 && beta2 > 0 && beta1 > 2 * beta2 && 1 + beta2 / 2 < beta1))
  {
    vtkErrorMacro(<< Label << ": the density thresholds SplitThreshold = " << beta1
                  << " and CollapseThreshold = " << beta2
                  << " do not converge; thesis 2.6.3 needs SplitThreshold > 2 x CollapseThreshold "
                     "and 1 + CollapseThreshold / 2 < SplitThreshold (defaults 1.5 and 0.67).");
    return 0;
  }
  if (!(this->QualityFloor > this->DegenerateThreshold))
  {
    vtkErrorMacro(<< Label << ": QualityFloor = " << this->QualityFloor
                  << " must be above DegenerateThreshold = " << this->DegenerateThreshold
                  << " (the stretch below which tetrahedra are removed; defaults 0.3 and 0.05).");
    return 0;
  }

  // The region restriction.
  std::vector<std::uint8_t> tetMask;
  if (!this->RegionArrayName.empty())
  {
    vtkDataArray* flags = input->GetCellData()->GetArray(this->RegionArrayName.c_str());
    if (!flags)
    {
      vtkErrorMacro(<< Label << ": RegionArrayName is '" << this->RegionArrayName
                    << "', but the input has no numeric cell array of that name.");
      return 0;
    }
    tetMask.resize(static_cast<std::size_t>(input->GetNumberOfCells()));
    std::size_t flagged = 0;
    for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
    {
      tetMask[static_cast<std::size_t>(c)] = flags->GetComponent(c, 0) != 0;
      flagged += tetMask[static_cast<std::size_t>(c)];
    }
    if (flagged == 0)
    {
      vtkWarningMacro(<< Label << ": no cell has a nonzero '" << this->RegionArrayName
                      << "'; the mesh is passed through unchanged.");
      output->ShallowCopy(input);
      return 1;
    }
  }

  const auto start = Clock::now();
  // Freed memory is reused during the run (vtkFEMorphHeapReuse.h), up to
  // the output, whose arrays outlive the filter.
  std::optional<vtkFEMorphHeapReuse> heapReuse;
  heapReuse.emplace();
  double segmentationSeconds = 0;
  bool aborted = false;
  try
  {
    // The segmentation: from the arrays, or made here.
    vtkSmartPointer<vtkUnstructuredGrid> working = input;
    vtkFEMorphSegmentationArrays::MeshSegmentation seg;
    femorph::Status read = vtkFEMorphSegmentationArrays::ReadFromMesh(input, Label, seg);
    bool haveSegmentation = read.ok;
    if (!haveSegmentation && this->SegmentIfMissing)
    {
      this->SetProgressText("segmenting the boundary");
      this->UpdateProgress(0.0);
      const auto t0 = Clock::now();
      femorph::TetMesh plain;
      femorph::BuildOptions bo;
      bo.allow_inverted = true;
      bo.allow_degenerate = true;
      const femorph::Status built = vtkFEMorphMeshConversion::ToTetMesh(input, Label, bo, plain);
      if (!built)
      {
        vtkErrorMacro(<< built.message);
        return 0;
      }
      femorph::SurfaceMesh surface;
      femorph::Segmentation segmentation;
      femorph::Status s = femorph::extract_boundary_surface(plain, surface);
      if (s)
      {
        s = femorph::segment_surface(surface, femorph::SegmentationParams(), segmentation);
      }
      if (s)
      {
        working = vtkSmartPointer<vtkUnstructuredGrid>::New();
        working->ShallowCopy(input);
        s = vtkFEMorphSegmentationArrays::WriteToMesh(surface, segmentation, working);
      }
      if (s)
      {
        read = vtkFEMorphSegmentationArrays::ReadFromMesh(working, Label, seg);
        s = read;
      }
      if (!s)
      {
        vtkErrorMacro(<< Label << ": the input has no segmentation arrays and segmenting it failed: "
                      << s.message);
        return 0;
      }
      vtkWarningMacro(<< Label << ": the input has no segmentation arrays (run FEMorph Segment "
                         "first to choose its settings); it was segmented with the default "
                         "settings into "
                      << segmentation.regions.size() << " regions.");
      haveSegmentation = true;
      segmentationSeconds = SecondsSince(t0);
    }
    else if (!haveSegmentation)
    {
      vtkWarningMacro(<< Label << ": " << read.message
                      << " SegmentIfMissing is off: every boundary vertex is kept where it is.");
    }
    if (this->CheckAbort())
    {
      return 1;
    }

    // The mesh; inverted tets are what Improve repairs.
    this->SetProgressText("converting the mesh");
    femorph::TetMesh mesh;
    femorph::BuildOptions options;
    options.allow_inverted = true;
    options.allow_degenerate = true;
    femorph::BuildReport buildReport;
    const femorph::Status converted =
      vtkFEMorphMeshConversion::ToTetMesh(working, Label, options, mesh, &buildReport);
    if (!converted)
    {
      vtkErrorMacro(<< converted.message);
      return 0;
    }
    femorph::BoundaryGeometry geometry;
    if (haveSegmentation)
    {
      geometry = MakeGeometry(seg);
    }

    // The target: density field and acceptable geometric error.
    std::vector<femorph::Vec3> points;
    std::vector<femorph::Tet> tets;
    GridArrays(working, points, tets);
    femorph::DensityGrid grid;
    std::vector<double> acceptable;
    // Repairing the poor elements only needs no density target.
    const bool wantDensity = !this->PoorElementsOnly;
    if (reference && reference->GetNumberOfCells() > 0)
    {
      std::string others;
      const vtkIdType n = vtkFEMorphMeshConversion::DescribeOtherCells(reference, VTK_TETRA, others);
      if (n > 0)
      {
        vtkErrorMacro(<< Label << ": the Reference mesh must hold tetrahedra only; it has " << others
                      << ".");
        return 0;
      }
      std::vector<femorph::Vec3> refPoints;
      std::vector<femorph::Tet> refTets;
      GridArrays(reference, refPoints, refTets);
      bool built = true;
      if (wantDensity)
      {
        double meanLength = 0;
        const std::vector<double> densities = femorph::vertex_density(refPoints, refTets, &meanLength);
        const double cell = this->GridCellSize > 0 ? this->GridCellSize : 0.5 * meanLength;
        // Eq. 2.33: with the input's connectivity the densities travel with
        // the material; otherwise the reference's field is used in space.
        const bool same = SameConnectivity(input, reference);
        // Improve looks the field up per cell (rho_GC), not trilinearly.
        constexpr std::size_t maxPoints = std::size_t(1) << 27;
        built = same ? grid.build(points, tets, densities, cell, maxPoints, false)
                     : grid.build(refPoints, refTets, densities, cell, maxPoints, false);
      }
      if (!built)
      {
        vtkWarningMacro(<< Label << ": no density field could be made from the Reference (grid "
                           "too fine or no tetrahedra); density control is off.");
      }
      vtkFEMorphSegmentationArrays::MeshSegmentation refSeg;
      if (haveSegmentation && vtkFEMorphSegmentationArrays::ReadFromMesh(reference, Label, refSeg).ok &&
        refSeg.RegionTypes.size() == seg.RegionTypes.size())
      {
        // From the reference's boundary faces as listed in FaceRegion: no
        // TetMesh of the reference is needed (0.7 s at 0.5M tets).
        acceptable =
          femorph::region_geometric_error(refPoints, refTets, refSeg.FaceRegions, MakeGeometry(refSeg));
        // A region whose type changed (e.g. a torus stretched into a
        // freeform face) has no target.
        for (std::size_t r = 0; r < acceptable.size(); ++r)
        {
          if (refSeg.RegionTypes[r] != seg.RegionTypes[r])
          {
            acceptable[r] = NaN;
          }
        }
      }
      else if (haveSegmentation)
      {
        vtkWarningMacro(<< Label << ": the Reference has no segmentation arrays matching the input's "
                           "regions; the input's own geometric error is kept.");
      }
    }
    else if (wantDensity)
    {
      double meanLength = 0;
      const std::vector<double> densities = femorph::vertex_density(points, tets, &meanLength);
      const double cell = this->GridCellSize > 0 ? this->GridCellSize : 0.5 * meanLength;
      grid.build(points, tets, densities, cell, std::size_t(1) << 27, false);
    }
    if (acceptable.empty() && haveSegmentation)
    {
      acceptable = femorph::region_geometric_error(mesh, geometry);
    }

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
    po.split_threshold = beta1;
    po.collapse_threshold = beta2;
    po.degenerate_threshold = this->DegenerateThreshold;
    po.quality_floor = this->QualityFloor;
    po.tet_mask = tetMask;
    po.fix_boundary = !haveSegmentation;
    po.trace_quality = this->TraceQuality != 0;
    po.poor_elements_only = this->PoorElementsOnly != 0;
    po.progress = [this, &aborted](double fraction, const char* phase) {
      this->SetProgressText(phase);
      this->UpdateProgress(0.05 + 0.9 * std::min(std::max(fraction, 0.0), 1.0));
      aborted = aborted || this->CheckAbort();
      return !aborted;
    };
    femorph::PhasedOdtTarget target;
    target.density = grid.empty() ? nullptr : &grid;
    target.acceptable_error = acceptable;
    const double preparationSeconds = SecondsSince(start) - segmentationSeconds;
    const femorph::PhasedOdtStats stats = femorph::phased_odt(mesh, geometry, target, po);
    const auto improveEnd = Clock::now();
    if (aborted)
    {
      return 1;
    }

    // Inverted tets no operation could repair.
    const std::size_t remaining = stats.remaining_inverted.size();
    if (remaining > 0 && this->RequireValid)
    {
      std::ostringstream where;
      const std::size_t shown = std::min<std::size_t>(remaining, 5);
      for (std::size_t i = 0; i < shown; ++i)
      {
        const femorph::Tet& T = mesh.tet(stats.remaining_inverted[i]);
        const femorph::Vec3 c =
          (mesh.point(T[0]) + mesh.point(T[1]) + mesh.point(T[2]) + mesh.point(T[3])) / 4;
        where << (i ? "; " : "") << "(" << c.x() << ", " << c.y() << ", " << c.z() << ")";
      }
      vtkErrorMacro(<< Label << ": " << remaining << " inverted tetrahedr" << (remaining == 1 ? "on" : "a")
                    << " could not be repaired by local operations (centres " << where.str()
                    << (remaining > shown ? "; ..." : "")
                    << "). Turn RequireValid off to get the mesh with them marked in the "
                       "'Inverted' cell array.");
      return 0;
    }

    this->SetProgressText("writing the output");
    const femorph::CompactMesh compact = mesh.compact();
    heapReuse.reset();
    vtkFEMorphMeshConversion::FromCompactMesh(compact, working, output);

    // Quality arrays.
    const vtkIdType numTets = static_cast<vtkIdType>(compact.tets.size());
    std::vector<double> stretch(compact.tets.size()), volume(compact.tets.size());
    femorph::compute_tet_quality(compact.points, compact.tets, stretch.data(), nullptr, nullptr, nullptr,
      volume.data());
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
    if (remaining > 0)
    {
      vtkWarningMacro(<< Label << ": " << remaining
                      << " inverted tetrahedra could not be repaired; they have Inverted = 1.");
    }
    // What limits the quality when the floor is not reached everywhere and
    // the boundary is the cause.
    if (stats.below_floor_on_boundary > 0)
    {
      vtkWarningMacro(<< Label << ": " << stats.below_floor << " tetrahedr"
                      << (stats.below_floor == 1 ? "on stays" : "a stay") << " below stretch "
                      << po.quality_floor << " (minimum " << std::round(1000 * stats.min_stretch_after) / 1000 << "); "
                      << stats.below_floor_on_boundary
                      << " of them have all four vertices on the boundary, so their shape is that of the "
                         "boundary triangles (typically a face much narrower than the mesh, such as a "
                         "strip between two curves). Only a finer surface mesh there would help; see "
                         "the Stretch cell array.");
    }

    // The curves' vertex lists in the output's numbering.
    vtkFieldData* fd = output->GetFieldData();
    if (haveSegmentation && !seg.CurveVertices.empty())
    {
      std::vector<std::vector<femorph::index_t>> oldCurves(seg.CurveVertices.size());
      std::vector<std::array<femorph::index_t, 2>> regions(seg.CurveVertices.size());
      for (std::size_t c = 0; c < seg.CurveVertices.size(); ++c)
      {
        oldCurves[c].assign(seg.CurveVertices[c].begin(), seg.CurveVertices[c].end());
        regions[c] = geometry.curve_regions[c];
      }
      const auto curves = femorph::trace_boundary_curves(compact, oldCurves, regions);
      vtkNew<vtkIdTypeArray> vertices;
      vertices->SetName(vtkFEMorphSegmentationArrays::CurveVerticesName);
      vtkNew<vtkIdTypeArray> offsets;
      offsets->SetName(vtkFEMorphSegmentationArrays::CurveOffsetsName);
      offsets->InsertNextValue(0);
      for (const auto& curve : curves)
      {
        for (const femorph::index_t v : curve)
        {
          vertices->InsertNextValue(v);
        }
        offsets->InsertNextValue(vertices->GetNumberOfTuples());
      }
      fd->AddArray(vertices);
      fd->AddArray(offsets);
    }

    // Summary.
    AddSummary(fd, "ImproveStretch",
      { { "MinBefore", stats.min_stretch_before }, { "MeanBefore", stats.mean_stretch_before },
        { "MinAfter", stats.min_stretch_after }, { "MeanAfter", stats.mean_stretch_after } });
    const bool density = target.density && po.density_control;
    AddSummary(fd, "ImproveDensityError",
      { { "Before", density ? stats.density_error_before.mean : NaN },
        { "After", density ? stats.density_error_after.mean : NaN } });
    const auto d = [](std::size_t n) { return static_cast<double>(n); };
    AddSummary(fd, "ImproveCounts",
      { { "Splits", d(stats.splits) }, { "Collapses", d(stats.collapses) },
        { "AccuracySplits", d(stats.accuracy_splits) }, { "Flips23", d(stats.flips_23) },
        { "Flips32", d(stats.flips_32) }, { "Flips44", d(stats.flips_44) },
        { "SurfaceFlips", d(stats.surface_flips) }, { "RemovedSlivers", d(stats.removed_slivers) },
        { "RemovedCaps", d(stats.removed_caps) }, { "RemovedSpades", d(stats.removed_spades) },
        { "RepairedInverted", d(stats.removed_inverted) }, { "RemainingInverted", d(remaining) },
        { "MovedVertices", d(stats.moved_vertices) }, { "BelowFloor", d(stats.below_floor) },
        { "BelowFloorAllBoundary", d(stats.below_floor_on_boundary) }, { "TetsBefore", d(stats.tets_before) },
        { "TetsAfter", d(stats.tets_after) }, { "LeftAsItWas", stats.skipped ? 1.0 : 0.0 } });
    AddSummary(fd, "ImproveTimes",
      { { "Segmentation", segmentationSeconds }, { "Curves", stats.phase_seconds[0] },
        { "Surfaces", stats.phase_seconds[1] }, { "Volume", stats.phase_seconds[2] },
        { "Total", SecondsSince(start) } });
    // The same time by step: set-up, the steps of Fig. 2.34 over all phases,
    // the output.
    std::vector<std::pair<const char*, double>> steps{ { "Preparation", preparationSeconds } };
    for (std::size_t i = 0; i < stats.step_seconds.size(); ++i)
    {
      steps.emplace_back(femorph::PhasedOdtStats::kStepNames[i], stats.step_seconds[i]);
    }
    steps.emplace_back("Output", SecondsSince(improveEnd));
    AddSummary(fd, "ImproveStepTimes", steps);
    if (this->TraceQuality)
    {
      // Seconds from the filter's start: the set-up before the loop first.
      vtkNew<vtkDoubleArray> trace;
      trace->SetName("ImproveQualityTrace");
      trace->SetNumberOfComponents(2);
      trace->SetComponentName(0, "Seconds");
      trace->SetComponentName(1, "MinStretch");
      for (const auto& point : stats.quality_trace)
      {
        const double tuple[2] = { segmentationSeconds + preparationSeconds + point[0], point[1] };
        trace->InsertNextTuple(tuple);
      }
      fd->AddArray(trace);
    }
    if (haveSegmentation)
    {
      AddPerRegion(fd, "GeometricError", stats.geometric_error_after);
      std::vector<double> target_error(geometry.regions.size(), NaN);
      for (std::size_t r = 0; r < target_error.size() && r < acceptable.size(); ++r)
      {
        target_error[r] = acceptable[r];
      }
      AddPerRegion(fd, "AcceptableGeometricError", target_error);
    }
  }
  catch (const std::bad_alloc&)
  {
    output->Initialize();
    vtkErrorMacro(<< Label << ": out of memory.");
    return 0;
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro(<< Label << " failed: " << e.what());
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}
