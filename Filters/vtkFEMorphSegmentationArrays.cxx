#include "vtkFEMorphSegmentationArrays.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "mesh/tet_mesh.h"
#include "mesh/trace_boundary_curves.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <utility>

namespace
{
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr int NumSurfaceTypes = static_cast<int>(femorph::SurfaceType::Unknown) + 1;
constexpr int NumCurveTypes = static_cast<int>(femorph::CurveType::Unclassified) + 1;

using femorph::Status;

template <class ArrayT>
vtkSmartPointer<ArrayT> NewArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

std::string Str(vtkIdType v)
{
  return std::to_string(v);
}

std::string Num(double v)
{
  std::ostringstream os;
  os << v;
  return os.str();
}

/// The length of the grid's bounding-box diagonal.
double Diagonal(vtkUnstructuredGrid* mesh)
{
  double b[6];
  mesh->GetBounds(b);
  return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
}

/// What makes a fitted surface unusable, e.g. "the radius -1 (a cylinder
/// needs a positive radius)"; empty when it is a surface. `diagonal`: the
/// part's size; a radius or distance a million times larger is no fit of it.
std::string SurfaceProblem(const femorph::SurfacePrimitive& s, double diagonal)
{
  using femorph::SurfaceType;
  if (s.type == SurfaceType::Unknown)
  {
    return std::string();
  }
  const double far = 1e6 * std::max(diagonal, std::numeric_limits<double>::min());
  const bool hasAxis = s.type != SurfaceType::Sphere;
  if (hasAxis && std::abs(s.axis.norm() - 1) > 1e-3)
  {
    return "the axis (" + Num(s.axis.x()) + ", " + Num(s.axis.y()) + ", " + Num(s.axis.z()) +
      ") (a unit vector is needed)";
  }
  const bool hasRadius = s.type == SurfaceType::Cylinder || s.type == SurfaceType::Sphere ||
    s.type == SurfaceType::Torus;
  if (hasRadius && !(s.radius > 0 && s.radius < far))
  {
    return "the radius " + Num(s.radius) + " (a positive radius below 1e6 times the part's size " +
      "is needed)";
  }
  if (s.type == SurfaceType::Torus && !(s.minor_radius > 0 && s.minor_radius < far))
  {
    return "the minor radius " + Num(s.minor_radius) + " (a positive radius is needed)";
  }
  if (s.type == SurfaceType::Cone && !(s.half_angle > 0 && s.half_angle < femorph::kPi / 2))
  {
    return "the half angle " + Num(s.half_angle) + " rad (it must lie in (0, pi / 2))";
  }
  return std::string();
}

// Local index (0..3) in `cell` of the vertex opposite the triangle whose
// mesh points are `tri`; -1 if the cell does not hold the triangle.
int OppositeLocal(const vtkIdType cell[4], const vtkIdType tri[3])
{
  int opposite = -1, matched = 0;
  for (int k = 0; k < 4; ++k)
  {
    const bool onTriangle = cell[k] == tri[0] || cell[k] == tri[1] || cell[k] == tri[2];
    if (onTriangle)
    {
      ++matched;
    }
    else
    {
      opposite = k;
    }
  }
  return matched == 3 ? opposite : -1;
}

// Reads a whole-number value; false for NaN, infinite or fractional values.
bool IntegerValue(double v, long long& out)
{
  if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 9.0e15)
  {
    return false;
  }
  out = static_cast<long long>(v);
  return true;
}

std::string NeighborText(const std::vector<femorph::index_t>& neighbors)
{
  std::ostringstream text;
  for (std::size_t i = 0; i < neighbors.size(); ++i)
  {
    text << (i ? " " : "") << neighbors[i];
  }
  return text.str();
}

const char* ConvexityText(femorph::Convexity c)
{
  switch (c)
  {
    case femorph::Convexity::Convex: return "convex";
    case femorph::Convexity::Concave: return "concave";
    default: return "";
  }
}
} // namespace

//------------------------------------------------------------------------------
const std::vector<std::string>& vtkFEMorphSegmentationArrays::RegionTableColumns()
{
  static const std::vector<std::string> columns = { "RegionId", "TypeName", "Radius",
    "MajorRadius", "MinorRadius", "HalfAngle", "Axis", "Center", "Apex", "Normal", "Point", "Area",
    "Convexity", "TriangleCount", "FitResidual", "Neighbors" };
  return columns;
}

//------------------------------------------------------------------------------
Status vtkFEMorphSegmentationArrays::Check(const femorph::SurfaceMesh& surface,
  const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh)
{
  const vtkIdType np = surface.num_points();
  const vtkIdType nf = surface.num_triangles();
  const vtkIdType nr = static_cast<vtkIdType>(segmentation.regions.size());
  const vtkIdType nc = static_cast<vtkIdType>(segmentation.curves.size());
  auto fail = [](const std::string& what) {
    return Status::failure("the segmentation does not fit the surface: " + what);
  };
  auto regionOk = [nr](femorph::index_t r) { return r >= -1 && r < nr; };

  if (static_cast<vtkIdType>(surface.source_vertex.size()) != np ||
    static_cast<vtkIdType>(surface.source_face.size()) != nf)
  {
    return fail("the surface does not record the mesh points and faces it comes from");
  }
  if (static_cast<vtkIdType>(segmentation.triangle_region.size()) != nf)
  {
    return fail(Str(static_cast<vtkIdType>(segmentation.triangle_region.size())) +
      " triangle regions for " + Str(nf) + " triangles");
  }
  for (vtkIdType f = 0; f < nf; ++f)
  {
    if (!regionOk(segmentation.triangle_region[f]))
    {
      return fail("triangle " + Str(f) + " has region " +
        Str(segmentation.triangle_region[f]) + " of " + Str(nr));
    }
  }
  if (static_cast<vtkIdType>(segmentation.vertex_class.size()) != np)
  {
    return fail(Str(static_cast<vtkIdType>(segmentation.vertex_class.size())) +
      " vertex classes for " + Str(np) + " vertices");
  }
  for (vtkIdType v = 0; v < np; ++v)
  {
    if (segmentation.vertex_class[v] < 0 || segmentation.vertex_class[v] > 3)
    {
      return fail("vertex " + Str(v) + " has class " +
        Str(segmentation.vertex_class[v]) + " (0 to 3)");
    }
  }
  for (vtkIdType r = 0; r < nr; ++r)
  {
    const femorph::Region& region = segmentation.regions[r];
    const int type = static_cast<int>(region.type);
    if (type < 0 || type >= NumSurfaceTypes)
    {
      return fail("region " + Str(r) + " has type code " + Str(type));
    }
    for (femorph::index_t n : region.neighbors)
    {
      if (n < 0 || n >= nr)
      {
        return fail("region " + Str(r) + " has neighbour " + Str(n) + " of " + Str(nr));
      }
    }
  }
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const femorph::BoundaryCurve& curve = segmentation.curves[c];
    const int type = static_cast<int>(curve.type);
    if (type < 0 || type >= NumCurveTypes)
    {
      return fail("curve " + Str(c) + " has type code " + Str(type));
    }
    if (!regionOk(curve.region_a) || !regionOk(curve.region_b))
    {
      return fail("curve " + Str(c) + " separates regions " + Str(curve.region_a) + " and " +
        Str(curve.region_b) + " of " + Str(nr));
    }
    if (curve.vertices.empty())
    {
      return fail("curve " + Str(c) + " has no vertices");
    }
    for (femorph::index_t v : curve.vertices)
    {
      if (v < 0 || v >= np)
      {
        return fail("curve " + Str(c) + " has vertex " + Str(v) + " of " + Str(np));
      }
    }
  }

  if (!mesh)
  {
    return Status::success();
  }
  const vtkIdType meshPoints = mesh->GetNumberOfPoints();
  const vtkIdType meshCells = mesh->GetNumberOfCells();
  for (vtkIdType v = 0; v < np; ++v)
  {
    if (surface.source_vertex[v] < 0 || surface.source_vertex[v] >= meshPoints)
    {
      return fail("surface vertex " + Str(v) + " comes from point " +
        Str(surface.source_vertex[v]) + " of a mesh with " + Str(meshPoints));
    }
  }
  vtkNew<vtkIdList> cellPoints;
  for (vtkIdType f = 0; f < nf; ++f)
  {
    const vtkIdType cell = surface.source_face[f] / 4;
    if (surface.source_face[f] < 0 || cell >= meshCells)
    {
      return fail("triangle " + Str(f) + " comes from cell " + Str(cell) + " of a mesh with " +
        Str(meshCells));
    }
    mesh->GetCellPoints(cell, cellPoints);
    if (cellPoints->GetNumberOfIds() != 4)
    {
      return fail("triangle " + Str(f) + " comes from cell " + Str(cell) + ", which has " +
        Str(cellPoints->GetNumberOfIds()) + " points instead of 4");
    }
    const femorph::Tri& t = surface.triangles[f];
    const vtkIdType tri[3] = { surface.source_vertex[t[0]], surface.source_vertex[t[1]],
      surface.source_vertex[t[2]] };
    if (OppositeLocal(cellPoints->GetPointer(0), tri) < 0)
    {
      return fail("triangle " + Str(f) + " is not a face of cell " + Str(cell));
    }
  }
  return Status::success();
}

//------------------------------------------------------------------------------
Status vtkFEMorphSegmentationArrays::WriteToMesh(const femorph::SurfaceMesh& surface,
  const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh)
{
  if (!mesh)
  {
    return Status::failure("no mesh to write the segmentation to");
  }
  const Status checked = Check(surface, segmentation, mesh);
  if (!checked)
  {
    return checked;
  }
  const vtkIdType numCells = mesh->GetNumberOfCells();
  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  const vtkIdType nr = static_cast<vtkIdType>(segmentation.regions.size());
  const vtkIdType nc = static_cast<vtkIdType>(segmentation.curves.size());

  // FaceRegion: the face opposite the cell's local vertex that is not on the
  // triangle (the grid's numbering, whatever orientation the core used).
  auto faceRegion = NewArray<vtkIntArray>(FaceRegionName, 4, numCells);
  faceRegion->Fill(-1);
  vtkNew<vtkIdList> cellPoints;
  for (femorph::index_t f = 0; f < surface.num_triangles(); ++f)
  {
    const vtkIdType cell = surface.source_face[f] / 4;
    mesh->GetCellPoints(cell, cellPoints);
    const femorph::Tri& t = surface.triangles[f];
    const vtkIdType tri[3] = { surface.source_vertex[t[0]], surface.source_vertex[t[1]],
      surface.source_vertex[t[2]] };
    const int local = OppositeLocal(cellPoints->GetPointer(0), tri);
    faceRegion->SetTypedComponent(cell, local, segmentation.triangle_region[f]);
  }
  mesh->GetCellData()->AddArray(faceRegion);

  auto vertexClass = NewArray<vtkUnsignedCharArray>(VertexClassName, 1, numPoints);
  vertexClass->Fill(0);
  for (femorph::index_t v = 0; v < surface.num_points(); ++v)
  {
    vertexClass->SetValue(
      surface.source_vertex[v], static_cast<unsigned char>(segmentation.vertex_class[v]));
  }
  mesh->GetPointData()->AddArray(vertexClass);

  vtkFieldData* fd = mesh->GetFieldData();
  auto regionType = NewArray<vtkIntArray>(RegionTypeName, 1, nr);
  auto regionParameters =
    NewArray<vtkDoubleArray>(RegionParametersName, femorph::kRegionParameterWidth, nr);
  auto regionConvexity = NewArray<vtkIntArray>(RegionConvexityName, 1, nr);
  for (vtkIdType r = 0; r < nr; ++r)
  {
    const femorph::Region& region = segmentation.regions[r];
    regionType->SetValue(r, static_cast<int>(region.type));
    const auto row = femorph::pack_region_parameters(region);
    regionParameters->SetTypedTuple(r, row.data());
    regionConvexity->SetValue(r, static_cast<int>(region.convexity));
  }
  fd->AddArray(regionType);
  fd->AddArray(regionParameters);
  fd->AddArray(regionConvexity);

  auto curveType = NewArray<vtkIntArray>(CurveTypeName, 1, nc);
  auto curveParameters =
    NewArray<vtkDoubleArray>(CurveParametersName, femorph::kCurveParameterWidth, nc);
  auto curveClosed = NewArray<vtkUnsignedCharArray>(CurveClosedName, 1, nc);
  auto curveOffsets = NewArray<vtkIdTypeArray>(CurveOffsetsName, 1, nc + 1);
  vtkIdType total = 0;
  curveOffsets->SetValue(0, 0);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const femorph::BoundaryCurve& curve = segmentation.curves[c];
    curveType->SetValue(c, static_cast<int>(curve.type));
    const auto row = femorph::pack_curve_parameters(curve);
    curveParameters->SetTypedTuple(c, row.data());
    curveClosed->SetValue(c, curve.closed ? 1 : 0);
    total += static_cast<vtkIdType>(curve.vertices.size());
    curveOffsets->SetValue(c + 1, total);
  }
  auto curveVertices = NewArray<vtkIdTypeArray>(CurveVerticesName, 1, total);
  vtkIdType at = 0;
  for (const femorph::BoundaryCurve& curve : segmentation.curves)
  {
    for (femorph::index_t v : curve.vertices)
    {
      curveVertices->SetValue(at++, surface.source_vertex[v]);
    }
  }
  fd->AddArray(curveType);
  fd->AddArray(curveParameters);
  fd->AddArray(curveClosed);
  fd->AddArray(curveVertices);
  fd->AddArray(curveOffsets);

  const femorph::SegmentationTimes& t = segmentation.times;
  const std::pair<const char*, double> steps[] = { { "SharpEdges", t.sharp_edges },
    { "Curvature", t.curvature }, { "Planes", t.planes }, { "Cylinders", t.cylinders },
    { "Cones", t.cones }, { "Spheres", t.spheres }, { "Tori", t.tori },
    { "Remaining", t.remaining }, { "Cleanup", t.cleanup }, { "Refinement", t.refinement },
    { "Curves", t.curves }, { "Total", t.total } };
  const int numSteps = static_cast<int>(sizeof(steps) / sizeof(steps[0]));
  auto times = NewArray<vtkDoubleArray>(SegmentationTimesName, numSteps, 1);
  for (int k = 0; k < numSteps; ++k)
  {
    times->SetComponentName(k, steps[k].first);
    times->SetTypedComponent(0, k, steps[k].second);
  }
  fd->AddArray(times);
  return Status::success();
}

//------------------------------------------------------------------------------
Status vtkFEMorphSegmentationArrays::WriteSurface(const femorph::SurfaceMesh& surface,
  const femorph::Segmentation& segmentation, vtkUnstructuredGrid* mesh, vtkPolyData* output)
{
  if (!output)
  {
    return Status::failure("no surface output to write to");
  }
  const Status checked = Check(surface, segmentation, mesh);
  if (!checked)
  {
    return checked;
  }
  output->Initialize();
  const vtkIdType np = surface.num_points();
  const vtkIdType nf = surface.num_triangles();
  const vtkIdType nc = static_cast<vtkIdType>(segmentation.curves.size());

  output->SetPoints(vtkFEMorphMeshConversion::NewPoints(surface.points));

  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(nf, 3 * nf);
  for (const femorph::Tri& t : surface.triangles)
  {
    const vtkIdType ids[3] = { t[0], t[1], t[2] };
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkCellArray> lines;
  std::vector<vtkIdType> ids;
  for (const femorph::BoundaryCurve& curve : segmentation.curves)
  {
    ids.assign(curve.vertices.begin(), curve.vertices.end());
    if (curve.closed)
    {
      ids.push_back(curve.vertices.front());
    }
    lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  output->SetPolys(polys);
  output->SetLines(lines);

  // Cell data: vtkPolyData numbers verts, lines, polys, strips in turn, so
  // the curves come first.
  auto regionId = NewArray<vtkIntArray>(RegionIdName, 1, nc + nf);
  auto regionType = NewArray<vtkIntArray>(RegionTypeName, 1, nc + nf);
  auto curveId = NewArray<vtkIntArray>(CurveIdName, 1, nc + nf);
  auto curveType = NewArray<vtkIntArray>(CurveTypeName, 1, nc + nf);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    regionId->SetValue(c, -1);
    regionType->SetValue(c, -1);
    curveId->SetValue(c, static_cast<int>(c));
    curveType->SetValue(c, static_cast<int>(segmentation.curves[c].type));
  }
  for (vtkIdType f = 0; f < nf; ++f)
  {
    const femorph::index_t r = segmentation.triangle_region[f];
    regionId->SetValue(nc + f, r);
    regionType->SetValue(nc + f, r >= 0 ? static_cast<int>(segmentation.regions[r].type) : -1);
    curveId->SetValue(nc + f, -1);
    curveType->SetValue(nc + f, -1);
  }
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(regionId);
  cd->AddArray(regionType);
  cd->AddArray(curveId);
  cd->AddArray(curveType);
  cd->SetActiveScalars(RegionIdName);

  // Point data: the mesh's, copied exactly (every surface vertex is a mesh
  // point), then the surface's own arrays.
  vtkPointData* pd = output->GetPointData();
  if (mesh)
  {
    vtkPointData* inPD = mesh->GetPointData();
    pd->CopyFieldOff(VertexClassName);
    pd->CopyFieldOff(MeshPointIdName);
    pd->CopyAllocate(inPD, np);
    for (vtkIdType v = 0; v < np; ++v)
    {
      pd->CopyData(inPD, surface.source_vertex[v], v);
    }
    pd->CopyFieldOn(VertexClassName);
    pd->CopyFieldOn(MeshPointIdName);
  }
  auto meshPointId = NewArray<vtkIdTypeArray>(MeshPointIdName, 1, np);
  auto vertexClass = NewArray<vtkUnsignedCharArray>(VertexClassName, 1, np);
  for (vtkIdType v = 0; v < np; ++v)
  {
    meshPointId->SetValue(v, surface.source_vertex[v]);
    vertexClass->SetValue(v, static_cast<unsigned char>(segmentation.vertex_class[v]));
  }
  pd->AddArray(meshPointId);
  pd->AddArray(vertexClass);
  return Status::success();
}

//------------------------------------------------------------------------------
Status vtkFEMorphSegmentationArrays::WriteRegionTable(
  const femorph::Segmentation& segmentation, vtkTable* output)
{
  if (!output)
  {
    return Status::failure("no table to write the regions to");
  }
  output->Initialize();
  const vtkIdType nr = static_cast<vtkIdType>(segmentation.regions.size());

  auto regionId = NewArray<vtkIntArray>("RegionId", 1, nr);
  auto typeName = NewArray<vtkStringArray>("TypeName", 1, nr);
  auto radius = NewArray<vtkDoubleArray>("Radius", 1, nr);
  auto majorRadius = NewArray<vtkDoubleArray>("MajorRadius", 1, nr);
  auto minorRadius = NewArray<vtkDoubleArray>("MinorRadius", 1, nr);
  auto halfAngle = NewArray<vtkDoubleArray>("HalfAngle", 1, nr);
  auto axis = NewArray<vtkDoubleArray>("Axis", 3, nr);
  auto center = NewArray<vtkDoubleArray>("Center", 3, nr);
  auto apex = NewArray<vtkDoubleArray>("Apex", 3, nr);
  auto normal = NewArray<vtkDoubleArray>("Normal", 3, nr);
  auto point = NewArray<vtkDoubleArray>("Point", 3, nr);
  auto area = NewArray<vtkDoubleArray>("Area", 1, nr);
  auto convexity = NewArray<vtkStringArray>("Convexity", 1, nr);
  auto triangleCount = NewArray<vtkIntArray>("TriangleCount", 1, nr);
  auto fitResidual = NewArray<vtkDoubleArray>("FitResidual", 1, nr);
  auto neighbors = NewArray<vtkStringArray>("Neighbors", 1, nr);
  for (vtkDoubleArray* a :
    { radius.Get(), majorRadius.Get(), minorRadius.Get(), halfAngle.Get(), axis.Get(),
      center.Get(), apex.Get(), normal.Get(), point.Get(), area.Get(), fitResidual.Get() })
  {
    a->Fill(NaN);
  }

  for (vtkIdType r = 0; r < nr; ++r)
  {
    const femorph::Region& region = segmentation.regions[r];
    const femorph::SurfacePrimitive& s = region.surface;
    const femorph::SurfaceType type = region.type;
    regionId->SetValue(r, static_cast<int>(r));
    typeName->SetValue(r, femorph::to_string(type));
    switch (type)
    {
      case femorph::SurfaceType::Plane:
        normal->SetTypedTuple(r, s.axis.data());
        point->SetTypedTuple(r, s.point.data());
        break;
      case femorph::SurfaceType::Cylinder:
        radius->SetValue(r, s.radius);
        axis->SetTypedTuple(r, s.axis.data());
        center->SetTypedTuple(r, s.point.data());
        break;
      case femorph::SurfaceType::Cone:
        halfAngle->SetValue(r, vtkMath::DegreesFromRadians(s.half_angle));
        axis->SetTypedTuple(r, s.axis.data());
        apex->SetTypedTuple(r, s.point.data());
        break;
      case femorph::SurfaceType::Sphere:
        radius->SetValue(r, s.radius);
        center->SetTypedTuple(r, s.point.data());
        break;
      case femorph::SurfaceType::Torus:
        majorRadius->SetValue(r, s.radius);
        minorRadius->SetValue(r, s.minor_radius);
        axis->SetTypedTuple(r, s.axis.data());
        center->SetTypedTuple(r, s.point.data());
        break;
      default: // Unknown: nothing fitted
        break;
    }
    area->SetValue(r, region.area);
    convexity->SetValue(r, ConvexityText(region.convexity));
    triangleCount->SetValue(r, static_cast<int>(region.triangle_count));
    if (type != femorph::SurfaceType::Unknown)
    {
      fitResidual->SetValue(r, region.fit_rms);
    }
    neighbors->SetValue(r, NeighborText(region.neighbors));
  }

  for (vtkAbstractArray* column : std::initializer_list<vtkAbstractArray*>{ regionId, typeName,
         radius, majorRadius, minorRadius, halfAngle, axis, center, apex, normal, point, area,
         convexity, triangleCount, fitResidual, neighbors })
  {
    output->AddColumn(column);
  }
  return Status::success();
}

//------------------------------------------------------------------------------
bool vtkFEMorphSegmentationArrays::HasSegmentation(vtkUnstructuredGrid* mesh)
{
  if (!mesh)
  {
    return false;
  }
  vtkFieldData* fd = mesh->GetFieldData();
  for (const char* name : { RegionTypeName, RegionParametersName, RegionConvexityName,
         CurveTypeName, CurveParametersName, CurveClosedName, CurveVerticesName, CurveOffsetsName })
  {
    if (fd->GetAbstractArray(name))
    {
      return true;
    }
  }
  return mesh->GetCellData()->GetAbstractArray(FaceRegionName) != nullptr;
}

//------------------------------------------------------------------------------
Status vtkFEMorphSegmentationArrays::ReadFromMesh(
  vtkUnstructuredGrid* mesh, MeshSegmentation& out, const std::string& gridName)
{
  out = MeshSegmentation();
  // Every message names the grid (the input, the Reference input...).
  auto fail = [&](const std::string& what) {
    out = MeshSegmentation();
    return Status::failure(what + " Run FEMorph Segment on the mesh first (and keep its arrays).");
  };
  const std::string of = " of " + gridName;
  if (!mesh)
  {
    return fail("there is no mesh.");
  }
  const vtkIdType numCells = mesh->GetNumberOfCells();
  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  vtkFieldData* fd = mesh->GetFieldData();

  // A numeric array of the expected shape, or a message saying why not.
  std::string problem;
  // `countedBy`: the array whose length gives `tuples`, for the message.
  auto numeric = [&](vtkFieldData* data, const char* kind, const char* name, int components,
                   vtkIdType tuples, const char* countedBy = nullptr) -> vtkDataArray* {
    vtkAbstractArray* a = data->GetAbstractArray(name);
    if (!a)
    {
      problem = gridName + " has no " + kind + " array " + name + ".";
      return nullptr;
    }
    vtkDataArray* d = vtkDataArray::SafeDownCast(a);
    if (!d)
    {
      problem = std::string("the ") + kind + " array " + name + of + " is not numeric.";
      return nullptr;
    }
    if (d->GetNumberOfComponents() != components)
    {
      problem = std::string("the ") + kind + " array " + name + of + " has " +
        Str(d->GetNumberOfComponents()) + " components instead of " + Str(components) + ".";
      return nullptr;
    }
    if (tuples >= 0 && d->GetNumberOfTuples() != tuples)
    {
      problem = std::string("the ") + kind + " array " + name + of + " has " +
        Str(d->GetNumberOfTuples()) + " values instead of " + Str(tuples) +
        (countedBy ? std::string(" (as many as ") + countedBy + " has)" : std::string()) + ".";
      return nullptr;
    }
    return d;
  };
  // Whole numbers in [lo, hi] in every component, or a message.
  // `why` (may be empty) says where the range comes from.
  auto integers = [&](vtkDataArray* d, long long lo, long long hi,
                    const std::function<void(vtkIdType, int, long long)>& store,
                    const std::string& why = std::string()) {
    const int nc = d->GetNumberOfComponents();
    for (vtkIdType i = 0; i < d->GetNumberOfTuples(); ++i)
    {
      for (int k = 0; k < nc; ++k)
      {
        long long v = 0;
        if (!IntegerValue(d->GetComponent(i, k), v) || v < lo || v > hi)
        {
          std::ostringstream value;
          value << d->GetComponent(i, k);
          problem = std::string("the array ") + d->GetName() + of + " has the value " + value.str() +
            " at " + Str(i) +
            (nc > 1 ? ", component " + Str(k) : std::string()) + " (expected a whole number in [" +
            std::to_string(lo) + ", " + std::to_string(hi) + "]" + (why.empty() ? "" : ", " + why) +
            ").";
          return false;
        }
        store(i, k, v);
      }
    }
    return true;
  };

  // Finite values in every component, or a message.
  auto finite = [&](vtkDataArray* d) {
    const int nc = d->GetNumberOfComponents();
    for (vtkIdType i = 0; i < d->GetNumberOfTuples(); ++i)
    {
      for (int k = 0; k < nc; ++k)
      {
        if (!std::isfinite(d->GetComponent(i, k)))
        {
          problem = std::string("the array ") + d->GetName() + of + " has a NaN or infinite value at " +
            Str(i) + ", component " + Str(k) + ".";
          return false;
        }
      }
    }
    return true;
  };

  // Regions.
  vtkDataArray* regionType = numeric(fd, "field", RegionTypeName, 1, -1);
  if (!regionType)
  {
    if (mesh->GetCellData()->GetAbstractArray(FaceRegionName) && !fd->GetAbstractArray(RegionTypeName))
    {
      problem = gridName + " has the cell array " + FaceRegionName + " but no field array " +
        RegionTypeName + " (the regions it names).";
    }
    return fail(problem);
  }
  const vtkIdType nr = regionType->GetNumberOfTuples();
  vtkDataArray* regionParameters =
    numeric(fd, "field", RegionParametersName, femorph::kRegionParameterWidth, nr, RegionTypeName);
  vtkDataArray* regionConvexity = regionParameters
    ? numeric(fd, "field", RegionConvexityName, 1, nr, RegionTypeName)
    : nullptr;
  if (!regionParameters || !regionConvexity)
  {
    return fail(problem);
  }
  out.RegionTypes.resize(static_cast<std::size_t>(nr));
  out.RegionConvexity.resize(static_cast<std::size_t>(nr));
  out.RegionParameters.resize(static_cast<std::size_t>(nr));
  out.RegionSurfaces.resize(static_cast<std::size_t>(nr));
  if (!integers(regionType, 0, NumSurfaceTypes - 1,
        [&](vtkIdType i, int, long long v) {
          out.RegionTypes[i] = static_cast<femorph::SurfaceType>(v);
        }) ||
    !integers(regionConvexity, 0, 2, [&](vtkIdType i, int, long long v) {
      out.RegionConvexity[i] = static_cast<femorph::Convexity>(v);
    }))
  {
    return fail(problem);
  }
  if (!finite(regionParameters))
  {
    return fail(problem);
  }
  for (vtkIdType r = 0; r < nr; ++r)
  {
    regionParameters->GetTuple(r, out.RegionParameters[r].data());
    out.RegionSurfaces[r] =
      femorph::unpack_region_surface(out.RegionTypes[r], out.RegionParameters[r].data());
    const std::string bad = SurfaceProblem(out.RegionSurfaces[r], Diagonal(mesh));
    if (!bad.empty())
    {
      return fail(std::string("the array ") + RegionParametersName + of + " gives region " +
        Str(r) + " (" + femorph::to_string(out.RegionTypes[r]) + ") " + bad + ".");
    }
  }

  // Faces.
  vtkDataArray* faceRegion = numeric(mesh->GetCellData(), "cell", FaceRegionName, 4, numCells);
  if (!faceRegion)
  {
    return fail(problem);
  }
  out.FaceRegions.resize(static_cast<std::size_t>(numCells));
  if (!integers(faceRegion, -1, nr - 1, [&](vtkIdType i, int k, long long v) {
        out.FaceRegions[i][k] = static_cast<femorph::index_t>(v);
      }))
  {
    return fail(problem);
  }

  // Vertex classes: optional.
  if (mesh->GetPointData()->GetAbstractArray(VertexClassName))
  {
    vtkDataArray* vertexClass =
      numeric(mesh->GetPointData(), "point", VertexClassName, 1, numPoints);
    if (!vertexClass)
    {
      return fail(problem);
    }
    out.VertexClasses.resize(static_cast<std::size_t>(numPoints));
    if (!integers(vertexClass, 0, 3, [&](vtkIdType i, int, long long v) {
          out.VertexClasses[i] = static_cast<std::uint8_t>(v);
        }))
    {
      return fail(problem);
    }
  }

  // Curves.
  vtkDataArray* curveType = numeric(fd, "field", CurveTypeName, 1, -1);
  if (!curveType)
  {
    return fail(problem);
  }
  const vtkIdType nc = curveType->GetNumberOfTuples();
  vtkDataArray* curveParameters =
    numeric(fd, "field", CurveParametersName, femorph::kCurveParameterWidth, nc, CurveTypeName);
  vtkDataArray* curveClosed =
    curveParameters ? numeric(fd, "field", CurveClosedName, 1, nc, CurveTypeName) : nullptr;
  vtkDataArray* curveOffsets = curveClosed
    ? numeric(fd, "field", CurveOffsetsName, 1, nc + 1, "CurveType, plus one")
    : nullptr;
  vtkDataArray* curveVertices =
    curveOffsets ? numeric(fd, "field", CurveVerticesName, 1, -1) : nullptr;
  if (!curveVertices)
  {
    return fail(problem);
  }
  out.CurveTypes.resize(static_cast<std::size_t>(nc));
  out.CurveParameters.resize(static_cast<std::size_t>(nc));
  out.CurveClosed.resize(static_cast<std::size_t>(nc));
  out.CurveVertices.resize(static_cast<std::size_t>(nc));
  const vtkIdType numCurveVertices = curveVertices->GetNumberOfTuples();
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(nc + 1));
  if (!integers(curveType, 0, NumCurveTypes - 1,
        [&](vtkIdType i, int, long long v) { out.CurveTypes[i] = static_cast<femorph::CurveType>(v); }) ||
    !integers(curveClosed, 0, 1, [&](vtkIdType i, int, long long v) { out.CurveClosed[i] = v != 0; }) ||
    !integers(curveOffsets, 0, numCurveVertices,
      [&](vtkIdType i, int, long long v) { offsets[i] = static_cast<vtkIdType>(v); },
      std::string(CurveVerticesName) + " has " + Str(numCurveVertices) + " values"))
  {
    return fail(problem);
  }
  if (offsets.front() != 0 || offsets.back() != numCurveVertices)
  {
    return fail(std::string("the array ") + CurveOffsetsName + of + " does not span " +
      CurveVerticesName + " (it runs from " + Str(offsets.front()) + " to " + Str(offsets.back()) +
      " of " + Str(numCurveVertices) + ").");
  }
  for (vtkIdType c = 0; c < nc; ++c)
  {
    if (offsets[c + 1] < offsets[c])
    {
      return fail(std::string("the array ") + CurveOffsetsName + of + " decreases at curve " + Str(c) +
        ".");
    }
  }
  std::vector<vtkIdType> vertices(static_cast<std::size_t>(numCurveVertices));
  if (!integers(curveVertices, 0, numPoints - 1,
        [&](vtkIdType i, int, long long v) { vertices[i] = static_cast<vtkIdType>(v); }))
  {
    return fail(problem);
  }
  if (!finite(curveParameters))
  {
    return fail(problem);
  }
  out.Curves.resize(static_cast<std::size_t>(nc));
  for (vtkIdType c = 0; c < nc; ++c)
  {
    curveParameters->GetTuple(c, out.CurveParameters[c].data());
    out.CurveVertices[c].assign(vertices.begin() + offsets[c], vertices.begin() + offsets[c + 1]);
    // The two regions and the continuity stored in the row.
    const double* row = out.CurveParameters[c].data();
    long long a = 0, b = 0, g = 0;
    if (!IntegerValue(row[17], a) || !IntegerValue(row[18], b) || a < -1 || a >= nr || b < -1 ||
      b >= nr || !IntegerValue(row[19], g) || g < 0 || g > 1)
    {
      return fail(std::string("the array ") + CurveParametersName + " names regions " +
        Num(row[17]) + " and " + Num(row[18]) + " (continuity " + Num(row[19]) + ") for curve " +
        Str(c) + "; the mesh has " + Str(nr) + " regions (ids 0 to " + Str(nr - 1) +
        ", -1 for none; continuity 0 or 1).");
    }
    femorph::BoundaryCurve& curve = out.Curves[c];
    curve = femorph::unpack_curve_parameters(out.CurveTypes[c], row);
    curve.id = static_cast<femorph::index_t>(c);
    curve.closed = out.CurveClosed[c];
    curve.vertices.assign(out.CurveVertices[c].begin(), out.CurveVertices[c].end());
  }
  return Status::success();
}

//------------------------------------------------------------------------------
femorph::Status vtkFEMorphSegmentationArrays::SegmentMesh(femorph::TetMesh& mesh,
  vtkUnstructuredGrid* input, vtkSmartPointer<vtkUnstructuredGrid>& working, MeshSegmentation& out,
  std::size_t& regionCount, const std::function<bool(double, const char*)>& progress)
{
  femorph::SurfaceMesh surface;
  femorph::Segmentation segmentation;
  const femorph::Status segmented =
    femorph::segment_boundary(mesh, femorph::SegmentationParams(), surface, segmentation, progress);
  if (!segmented)
  {
    return segmented;
  }
  working = vtkSmartPointer<vtkUnstructuredGrid>::New();
  working->ShallowCopy(input);
  femorph::Status status = WriteToMesh(surface, segmentation, working);
  if (status)
  {
    status = ReadFromMesh(working, out);
  }
  if (!status)
  {
    return status;
  }
  for (femorph::index_t f = 0; f < surface.num_triangles(); ++f)
  {
    const femorph::index_t code = surface.source_face[f];
    mesh.set_face_region(code / 4, code % 4, segmentation.triangle_region[f]);
  }
  mesh.classify_vertices();
  regionCount = segmentation.regions.size();
  return femorph::Status::success();
}

//------------------------------------------------------------------------------
std::vector<std::vector<femorph::index_t>> vtkFEMorphSegmentationArrays::WriteTracedCurves(
  const femorph::CompactMesh& compact, const std::vector<femorph::BoundaryCurve>& curves,
  const std::vector<std::array<femorph::index_t, 2>>& curveRegions, vtkFieldData* fd)
{
  std::vector<std::vector<femorph::index_t>> oldCurves(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c)
  {
    oldCurves[c] = curves[c].vertices;
  }
  vtkNew<vtkIdTypeArray> vertices;
  vertices->SetName(CurveVerticesName);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetName(CurveOffsetsName);
  offsets->InsertNextValue(0);
  std::vector<std::vector<femorph::index_t>> traced =
    femorph::trace_boundary_curves(compact, oldCurves, curveRegions);
  for (const auto& curve : traced)
  {
    for (const femorph::index_t v : curve)
    {
      vertices->InsertNextValue(v);
    }
    offsets->InsertNextValue(vertices->GetNumberOfTuples());
  }
  fd->AddArray(vertices);
  fd->AddArray(offsets);
  return traced;
}
