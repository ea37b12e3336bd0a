#include "vtkFEMorphDeform.h"

#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "deform/deform.h"
#include "geometry/curve_primitive.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

vtkStandardNewMacro(vtkFEMorphDeform);

namespace
{
using femorph::index_t;

/// The region of the boundary face nearest to `p`.
index_t NearestRegion(const femorph::TetMesh& mesh, const femorph::Vec3& p)
{
  double best = std::numeric_limits<double>::infinity();
  index_t region = femorph::kInvalidIndex;
  for (index_t t = 0; t < mesh.tet_slots(); ++t)
  {
    if (!mesh.tet_alive(t))
    {
      continue;
    }
    for (int f = 0; f < 4; ++f)
    {
      const index_t r = mesh.face_region(t, f);
      if (r < 0)
      {
        continue;
      }
      const femorph::Tet& T = mesh.tet(t);
      const femorph::Vec3& a = mesh.point(T[femorph::kTetFace[f][0]]);
      const femorph::Vec3& b = mesh.point(T[femorph::kTetFace[f][1]]);
      const femorph::Vec3& c = mesh.point(T[femorph::kTetFace[f][2]]);
      // Distance to the triangle: its plane within it, else its edges.
      const femorph::Vec3 n = (b - a).cross(c - a);
      double d = std::numeric_limits<double>::infinity();
      if (n.squaredNorm() > 0)
      {
        const femorph::Vec3 q = p - n.dot(p - a) / n.squaredNorm() * n;
        const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
          (a - c).cross(q - c).dot(n) >= 0;
        if (inside)
        {
          d = (p - q).norm();
        }
      }
      const femorph::Vec3* e[3][2] = { { &a, &b }, { &b, &c }, { &c, &a } };
      for (const auto& edge : e)
      {
        const femorph::Vec3 u = *edge[1] - *edge[0];
        const double s = std::clamp(u.dot(p - *edge[0]) / std::max(u.squaredNorm(), 1e-300), 0.0, 1.0);
        d = std::min(d, (p - (*edge[0] + s * u)).norm());
      }
      if (d < best)
      {
        best = d;
        region = r;
      }
    }
  }
  return region;
}

/// RegionParameters with the deformed surfaces (columns 0-8; the fit
/// statistics and area of the input kept).
void UpdateRegionParameters(
  vtkFieldData* fd, const std::vector<femorph::SurfacePrimitive>& surfaces, vtkFieldData* source)
{
  auto* old = vtkDoubleArray::SafeDownCast(
    source->GetAbstractArray(vtkFEMorphSegmentationArrays::RegionParametersName));
  if (!old || old->GetNumberOfTuples() != static_cast<vtkIdType>(surfaces.size()))
  {
    return;
  }
  vtkNew<vtkDoubleArray> array;
  array->DeepCopy(old);
  for (std::size_t r = 0; r < surfaces.size(); ++r)
  {
    const femorph::SurfacePrimitive& s = surfaces[r];
    const double values[9] = { s.point.x(), s.point.y(), s.point.z(), s.axis.x(), s.axis.y(),
      s.axis.z(), s.radius, s.minor_radius, s.half_angle };
    for (int k = 0; k < 9; ++k)
    {
      array->SetComponent(static_cast<vtkIdType>(r), k, values[k]);
    }
  }
  fd->RemoveArray(vtkFEMorphSegmentationArrays::RegionParametersName);
  fd->AddArray(array);
}

/// CurveParameters refitted on the traced curves of the output (the curves
/// of moved and deformed regions changed).
void RefitCurves(vtkFieldData* fd, const femorph::CompactMesh& compact,
  const std::vector<std::vector<index_t>>& traced, const std::vector<femorph::BoundaryCurve>& curves,
  const std::vector<femorph::SurfacePrimitive>& surfaces, const std::vector<femorph::RegionRole>& roles,
  double tolerance)
{
  auto* params = vtkDoubleArray::SafeDownCast(
    fd->GetAbstractArray(vtkFEMorphSegmentationArrays::CurveParametersName));
  if (!params || params->GetNumberOfTuples() != static_cast<vtkIdType>(curves.size()) ||
    traced.size() != curves.size())
  {
    return;
  }
  vtkNew<vtkDoubleArray> array;
  array->DeepCopy(params);
  const auto fixed = [&](index_t r) {
    return r < 0 || r >= static_cast<index_t>(roles.size()) || roles[r] == femorph::RegionRole::Fixed;
  };
  for (std::size_t c = 0; c < curves.size(); ++c)
  {
    femorph::BoundaryCurve curve = curves[c];
    if ((fixed(curve.region_a) && fixed(curve.region_b)) || traced[c].size() < 2)
    {
      continue;
    }
    std::vector<femorph::Vec3> points;
    for (const index_t v : traced[c])
    {
      points.push_back(compact.points[v]);
    }
    const femorph::SurfacePrimitive none;
    const auto surface = [&](index_t r) {
      return r >= 0 && r < static_cast<index_t>(surfaces.size()) ? surfaces[r] : none;
    };
    const femorph::CurveFit fit = femorph::classify_boundary_curve(
      points, curve.closed, tolerance, surface(curve.region_a), surface(curve.region_b));
    if (!fit.ok)
    {
      continue;
    }
    curve.curve = fit.curve;
    curve.type = fit.curve.type;
    const auto row = femorph::pack_curve_parameters(curve);
    for (int k = 0; k < femorph::kCurveParameterWidth; ++k)
    {
      array->SetComponent(static_cast<vtkIdType>(c), k, row[static_cast<std::size_t>(k)]);
    }
  }
  fd->RemoveArray(vtkFEMorphSegmentationArrays::CurveParametersName);
  fd->AddArray(array);
}
}

//------------------------------------------------------------------------------
vtkFEMorphDeform::vtkFEMorphDeform()
  : vtkFEMorphAlgorithm("FEMorph Deform", Tetrahedra)
{
  const femorph::DeformOptions options;
  const femorph::DeformMeshOptions meshOptions;
  this->LocalRegion = options.local_region;
  this->Improve = meshOptions.improve;
  this->MaxStepFraction = meshOptions.max_step_fraction;
  this->MaxSteps = meshOptions.max_steps;
  this->QualityFloor = meshOptions.quality_floor;
}

vtkFEMorphDeform::~vtkFEMorphDeform() = default;

void vtkFEMorphDeform::AddReferenceRegion(int id)
{
  this->ReferenceRegions.push_back(id);
  this->Modified();
}
void vtkFEMorphDeform::RemoveAllReferenceRegions()
{
  if (!this->ReferenceRegions.empty())
  {
    this->ReferenceRegions.clear();
    this->Modified();
  }
}
int vtkFEMorphDeform::GetReferenceRegion(int i) const
{
  return i >= 0 && i < this->GetNumberOfReferenceRegions() ? this->ReferenceRegions[i] : -1;
}
void vtkFEMorphDeform::AddFollowingRegion(int id)
{
  this->FollowingRegions.push_back(id);
  this->Modified();
}
void vtkFEMorphDeform::RemoveAllFollowingRegions()
{
  if (!this->FollowingRegions.empty())
  {
    this->FollowingRegions.clear();
    this->Modified();
  }
}
int vtkFEMorphDeform::GetFollowingRegion(int i) const
{
  return i >= 0 && i < this->GetNumberOfFollowingRegions() ? this->FollowingRegions[i] : -1;
}

//------------------------------------------------------------------------------
void vtkFEMorphDeform::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DeformationType: " << this->DeformationType << "\n";
  os << indent << "ControlRegion: " << this->ControlRegion << "\n";
  os << indent << "ControlPoint: " << this->ControlPoint[0] << " " << this->ControlPoint[1] << " "
     << this->ControlPoint[2] << "\n";
  os << indent << "UseControlPoint: " << this->UseControlPoint << "\n";
  os << indent << "ReferenceRegions:";
  for (const int r : this->ReferenceRegions)
  {
    os << " " << r;
  }
  os << "\n" << indent << "FollowingRegions:";
  for (const int r : this->FollowingRegions)
  {
    os << " " << r;
  }
  os << "\n" << indent << "TargetValue: " << this->TargetValue << "\n";
  os << indent << "Translation: " << this->Translation[0] << " " << this->Translation[1] << " "
     << this->Translation[2] << "\n";
  os << indent << "LocalRegion: " << this->LocalRegion << "\n";
  os << indent << "Improve: " << this->Improve << "\n";
  os << indent << "MaxStepFraction: " << this->MaxStepFraction << "\n";
  os << indent << "MaxSteps: " << this->MaxSteps << "\n";
  os << indent << "QualityFloor: " << this->QualityFloor << "\n";
}

//------------------------------------------------------------------------------
bool vtkFEMorphDeform::CheckProperties()
{
  if (!(this->CheckRange("MaxStepFraction", this->MaxStepFraction, 0.001, 1) &&
        this->CheckRange("QualityFloor", this->QualityFloor, 0.05, 0.6)))
  {
    return false;
  }
  if (!this->CheckRange("TargetValue", this->TargetValue, -1e300, 1e300, "0 (the default) measures only"))
  {
    return false;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (!std::isfinite(this->Translation[k]) ||
      (this->UseControlPoint && !std::isfinite(this->ControlPoint[k])))
    {
      this->Fail("Translation and ControlPoint must be finite.");
      return false;
    }
  }
  if (this->ControlRegion < 0 && !this->UseControlPoint)
  {
    this->Fail("no control region: set ControlRegion (an id of FEMorph Segment's Regions table) or "
               "ControlPoint with UseControlPoint on.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkFEMorphDeform::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector** /*inputVector*/, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkSmartPointer<vtkUnstructuredGrid> working = input;
  vtkFEMorphSegmentationArrays::MeshSegmentation seg;
  const bool haveSegmentation = vtkFEMorphSegmentationArrays::HasSegmentation(input);
  if (haveSegmentation && !this->Check(vtkFEMorphSegmentationArrays::ReadFromMesh(input, seg)))
  {
    return false;
  }
  this->Progress(0.0, "converting the mesh");
  femorph::TetMesh mesh;
  femorph::BuildOptions buildOptions;
  buildOptions.face_regions = seg.FaceRegions;
  if (!this->ToTetMesh(input, buildOptions, mesh))
  {
    return false;
  }
  const std::vector<femorph::Vec3> inputPoints = mesh.points();
  if (!haveSegmentation)
  {
    std::size_t regionCount = 0;
    const femorph::Status segmented = vtkFEMorphSegmentationArrays::SegmentMesh(
      mesh, input, working, seg, regionCount, this->ProgressRange(0.0, 0.1));
    if (this->WasAborted())
    {
      return true;
    }
    if (!segmented)
    {
      this->Fail("the input has no segmentation arrays and segmenting it failed: " + segmented.message);
      return false;
    }
    this->Warn("the input has no segmentation arrays (run FEMorph Segment first to choose its "
               "settings and see the region ids); it was segmented with the default settings into " +
      std::to_string(regionCount) + " regions.");
  }

  femorph::DeformRegions regions;
  regions.surfaces = seg.RegionSurfaces;
  regions.convexity = seg.RegionConvexity;
  femorph::DeformOptions options;
  options.type = static_cast<femorph::DeformationType>(this->DeformationType);
  options.control_region = this->ControlRegion;
  if (options.control_region < 0)
  {
    const femorph::Vec3 p(this->ControlPoint[0], this->ControlPoint[1], this->ControlPoint[2]);
    options.control_region = NearestRegion(mesh, p);
    if (options.control_region < 0)
    {
      this->Fail("no boundary face of the mesh has a region; run FEMorph Segment first.");
      return false;
    }
  }
  options.reference_regions.assign(this->ReferenceRegions.begin(), this->ReferenceRegions.end());
  if (!this->FollowingRegions.empty())
  {
    options.override_following = true;
    for (const int r : this->FollowingRegions)
    {
      if (r != -1)
      {
        options.following_regions.push_back(r);
      }
    }
  }
  options.translation =
    femorph::Vec3(this->Translation[0], this->Translation[1], this->Translation[2]);
  options.local_region = this->LocalRegion != 0;

  femorph::DeformMeshOptions meshOptions;
  // No target (0, never a valid dimension): measure only. Position moves
  // by |Translation| unless TargetValue gives the distance.
  const bool noTarget = this->TargetValue == 0;
  meshOptions.target = noTarget ? std::numeric_limits<double>::quiet_NaN() : this->TargetValue;
  if (options.type == femorph::DeformationType::Position && noTarget && options.translation.norm() > 0)
  {
    meshOptions.target = options.translation.norm();
  }
  meshOptions.improve = this->Improve != 0;
  meshOptions.max_step_fraction = this->MaxStepFraction;
  meshOptions.max_steps = this->MaxSteps;
  meshOptions.quality_floor = this->QualityFloor;
  meshOptions.progress = this->ProgressRange(0.1, 0.95);
  femorph::DeformPlan plan;
  femorph::DeformReport report;
  if (!meshOptions.improve && !std::isnan(meshOptions.target))
  {
    // Parameterise once, reposition many: the session is kept while the
    // input and every property but TargetValue stay the same.
    std::ostringstream key;
    key << input << " " << input->GetMTime() << " " << static_cast<int>(options.type) << " "
        << options.control_region << " " << options.local_region << " " << options.translation.transpose()
        << " r";
    for (const auto r : options.reference_regions)
    {
      key << " " << r;
    }
    key << " f" << options.override_following;
    for (const auto r : options.following_regions)
    {
      key << " " << r;
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (!this->Session || this->SessionKey != key.str())
    {
      this->Session = std::make_shared<femorph::DeformSession>();
      this->SessionKey.clear();
      const femorph::Status prepared = this->Session->prepare(mesh, regions, options);
      if (!prepared)
      {
        this->Session.reset();
        this->Fail(prepared.message);
        return false;
      }
      this->SessionKey = key.str();
    }
    std::vector<femorph::Vec3> points;
    bool reused = false;
    const femorph::Status moved =
      this->Session->reposition(meshOptions.target, points, report.surfaces, &reused);
    plan = this->Session->plan();
    if (!moved)
    {
      this->Fail(moved.message);
      return false;
    }
    for (femorph::index_t v = 0; v < mesh.vertex_slots(); ++v)
    {
      if (mesh.vertex_alive(v) && points[v] != mesh.point(v))
      {
        mesh.set_point(v, points[v]);
        ++report.moved_vertices;
      }
    }
    const auto& param = this->Session->parameterization();
    report.current = plan.current;
    report.target = meshOptions.target;
    report.valid_min = plan.valid_min;
    report.valid_max = plan.valid_max;
    report.steps = 1;
    report.deformable = param.deformable;
    if (report.deformable.empty())
    {
      report.deformable.assign(static_cast<std::size_t>(mesh.tet_slots()), 1);
    }
    report.surface_unknowns = param.surfaces.unknowns.size() + param.curves.unknowns.size();
    report.inner_unknowns = param.inner.unknowns.size();
    report.seconds_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    (reused ? report.seconds_reposition : report.seconds_parameterize) = report.seconds_total;
    report.min_stretch_before = report.min_stretch_after = std::numeric_limits<double>::quiet_NaN();
  }
  else
  {
    const femorph::Status deformed =
      femorph::deform_mesh(mesh, regions, &seg.Curves, options, meshOptions, plan, report);
    if (this->WasAborted() || report.aborted)
    {
      return true;
    }
    if (!deformed)
    {
      this->Fail(deformed.message);
      return false;
    }
  }
  this->WarnAll(report.warnings);

  this->Progress(0.95, "writing the output");
  const femorph::CompactMesh compact = mesh.compact();
  this->FromCompactMesh(compact, working, output);
  const vtkIdType numPoints = static_cast<vtkIdType>(compact.points.size());
  const vtkIdType numTets = static_cast<vtkIdType>(compact.tets.size());

  // Displacement from the input position (interpolated for new points).
  vtkNew<vtkDoubleArray> displacement;
  displacement->SetName("Displacement");
  displacement->SetNumberOfComponents(3);
  displacement->SetNumberOfTuples(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    femorph::Vec3 from = femorph::Vec3::Zero();
    const femorph::VertexStencil& stencil = compact.vertex_origin[static_cast<std::size_t>(i)];
    double sum = 0;
    for (int k = 0; k < 4; ++k)
    {
      const index_t v = stencil.ids[k];
      if (v >= 0 && v < static_cast<index_t>(inputPoints.size()))
      {
        from += stencil.weights[k] * inputPoints[v];
        sum += stencil.weights[k];
      }
    }
    const femorph::Vec3 d =
      sum > 0 ? femorph::Vec3(compact.points[static_cast<std::size_t>(i)] - from / sum) : femorph::Vec3::Zero();
    displacement->SetTuple3(i, d.x(), d.y(), d.z());
  }
  output->GetPointData()->AddArray(displacement);

  // Roles per face, the deformable flag and the stretch per cell.
  vtkNew<vtkIntArray> roles;
  roles->SetName("RegionRole");
  roles->SetNumberOfComponents(4);
  roles->SetNumberOfTuples(numTets);
  vtkNew<vtkUnsignedCharArray> deformable;
  deformable->SetName("Deformable");
  deformable->SetNumberOfTuples(numTets);
  vtkNew<vtkDoubleArray> stretch;
  stretch->SetName("Stretch");
  stretch->SetNumberOfTuples(numTets);
  for (vtkIdType t = 0; t < numTets; ++t)
  {
    const auto& regionsOfTet = compact.face_regions[static_cast<std::size_t>(t)];
    for (int f = 0; f < 4; ++f)
    {
      const index_t r = regionsOfTet[static_cast<std::size_t>(f)];
      roles->SetComponent(t, f,
        r >= 0 && r < static_cast<index_t>(plan.roles.size()) ? static_cast<int>(plan.roles[r]) : -1);
    }
    const index_t origin = compact.tet_origin[static_cast<std::size_t>(t)];
    deformable->SetValue(t,
      origin >= 0 && origin < static_cast<index_t>(report.deformable.size()) ? report.deformable[origin] : 0);
    const femorph::Tet& T = compact.tets[static_cast<std::size_t>(t)];
    stretch->SetValue(t,
      femorph::tet_stretch(compact.points[T[0]], compact.points[T[1]], compact.points[T[2]], compact.points[T[3]]));
  }
  output->GetCellData()->AddArray(roles);
  output->GetCellData()->AddArray(deformable);
  output->GetCellData()->AddArray(stretch);

  // The segmentation of the deformed part.
  vtkFieldData* fd = output->GetFieldData();
  UpdateRegionParameters(fd, report.surfaces, working->GetFieldData());
  if (!seg.Curves.empty())
  {
    std::vector<std::array<index_t, 2>> curveRegions;
    for (const femorph::BoundaryCurve& c : seg.Curves)
    {
      curveRegions.push_back({ c.region_a, c.region_b });
    }
    const auto traced = vtkFEMorphSegmentationArrays::WriteTracedCurves(compact, seg.Curves, curveRegions, fd);
    RefitCurves(fd, compact, traced, seg.Curves, report.surfaces, plan.roles, 1e-6 * plan.part_size);
  }

  // The summary.
  AddValue(fd, "CurrentDimension", report.current);
  AddValue(fd, "TargetDimension", report.target);
  AddSummary(fd, "ValidRange", { { "Min", report.valid_min }, { "Max", report.valid_max } });
  AddCount(fd, "DeformSteps", report.steps);
  std::vector<double> reference(plan.reference.begin(), plan.reference.end());
  AddValues(fd, "ReferenceRegions", reference);
  std::vector<double> regionRoles;
  for (const femorph::RegionRole role : plan.roles)
  {
    regionRoles.push_back(static_cast<double>(role));
  }
  AddValues(fd, "RegionRoles", regionRoles);
  AddValue(fd, "ControlRegion", options.control_region);
  const auto d = [](std::size_t n) { return static_cast<double>(n); };
  std::size_t deformableTets = 0;
  for (const auto flag : report.deformable)
  {
    deformableTets += flag;
  }
  AddSummary(fd, "DeformCounts",
    { { "MovedVertices", d(report.moved_vertices) }, { "DeformableTets", d(deformableTets) },
      { "SurfaceUnknowns", d(report.surface_unknowns) }, { "InnerUnknowns", d(report.inner_unknowns) },
      { "InvertedBeforeImprove", d(report.inverted_before_improve) },
      { "TetsBefore", d(static_cast<std::size_t>(input->GetNumberOfCells())) },
      { "TetsAfter", d(compact.tets.size()) } });
  AddSummary(fd, "DeformStretch",
    { { "MinBefore", report.min_stretch_before }, { "MinAfter", report.min_stretch_after } });
  AddSummary(fd, "DeformTimes",
    { { "Classify", report.seconds_classify }, { "ValidRange", report.seconds_range },
      { "Parameterize", report.seconds_parameterize }, { "Reposition", report.seconds_reposition },
      { "Improve", report.seconds_improve }, { "Total", report.seconds_total } });
  return true;
}
