// vtkFEMorphSegmentationArrays on a hand-built segmentation of a cube mesh:
// the mesh arrays, the surface with its polylines, the region table (every
// column, NaN where it does not apply) and the reader, also after a round
// trip through a .vtu file; the reader's and writers' refusals; the packing
// contract of Core/segment/segmentation.h. Independent of segment_surface.
#include "../test_meshes.h"
#include "filters_test_utils.h"
#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphSegmentationArrays.h"

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
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUnstructuredGridWriter.h"

#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

using Arrays = vtkFEMorphSegmentationArrays;
using femorph::SurfaceType;

namespace
{
constexpr int N = 2; // cube cells per side
constexpr double Tol = 1e-12;

// The cube plane a point lies on: region 2 * axis + side (0: x=0, 1: x=1,
// 2: y=0 ... as make_cube_mesh numbers them); the count of such planes.
int PlanesOf(const double p[3], int regions[3])
{
  int count = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = 0; side < 2; ++side)
    {
      if (p[axis] == side)
      {
        regions[count++] = 2 * axis + side;
      }
    }
  }
  return count;
}

// The region of the face with these three points, or -1 (interior).
int FaceRegionOf(vtkPoints* points, const vtkIdType ids[3])
{
  int common = -1;
  for (int region = 0; region < 6; ++region)
  {
    bool all = true;
    for (int k = 0; k < 3; ++k)
    {
      double p[3];
      points->GetPoint(ids[k], p);
      all = all && p[region / 2] == region % 2;
    }
    if (all)
    {
      common = region;
    }
  }
  return common;
}

// The cube as a grid; `flipped`: every tet with the opposite vertex order
// (the core flips them back; the arrays must use the grid's numbering).
vtkSmartPointer<vtkUnstructuredGrid> MakeCubeGrid(bool flipped)
{
  const femorph::testing::TestMesh cube = femorph::testing::make_cube_mesh(N, 0.0, 1);
  std::vector<std::array<double, 3>> points;
  for (const femorph::Vec3& p : cube.points)
  {
    points.push_back({ p.x(), p.y(), p.z() });
  }
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  for (const femorph::Tet& t : cube.tets)
  {
    cells.push_back({ VTK_TETRA,
      flipped ? std::vector<vtkIdType>{ t[0], t[2], t[1], t[3] }
              : std::vector<vtkIdType>{ t[0], t[1], t[2], t[3] } });
  }
  auto grid = femorph_test::MakeGrid(points, cells);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    temperature->InsertNextValue(10.0 + 0.25 * i);
  }
  grid->GetPointData()->AddArray(temperature);
  return grid;
}

// Parameters of the hand-built regions: region r gets type r (plane,
// cylinder, cone, sphere, torus, unknown), whatever its geometry.
femorph::SurfacePrimitive MadeUpSurface(int r)
{
  femorph::SurfacePrimitive s;
  s.type = static_cast<SurfaceType>(r);
  s.point = femorph::Vec3(0.5 + r, -1.25 * r, 2.0 + 0.125 * r);
  s.axis = femorph::Vec3(r % 2, (r + 1) % 2, 0.0);
  switch (s.type)
  {
    case SurfaceType::Cylinder: s.radius = 12; break;
    case SurfaceType::Cone: s.half_angle = vtkMath::RadiansFromDegrees(45.0); break;
    case SurfaceType::Sphere: s.radius = 6.5; break;
    case SurfaceType::Torus:
      s.radius = 15;
      s.minor_radius = 3;
      break;
    default: break;
  }
  if (s.type == SurfaceType::Unknown)
  {
    s = femorph::SurfacePrimitive();
  }
  return s;
}

struct Fixture
{
  vtkSmartPointer<vtkUnstructuredGrid> Input;
  femorph::SurfaceMesh Surface;
  femorph::Segmentation Segmentation;
};

// The cube's boundary surface through the core and a segmentation of it
// built by hand: six regions (one per face), 4 vertical edges as open line
// curves and the top and bottom loops as closed curves.
void MakeFixture(bool flipped, Fixture& f)
{
  f.Input = MakeCubeGrid(flipped);
  femorph::TetMesh mesh;
  femorph::BuildReport report;
  const femorph::Status converted =
    vtkFEMorphMeshConversion::ToTetMesh(f.Input, {}, mesh, &report);
  ASSERT_TRUE(converted) << converted.message;
  EXPECT_EQ(report.flipped_tets, flipped ? static_cast<std::size_t>(f.Input->GetNumberOfCells()) : 0u);
  const femorph::Status extracted = femorph::extract_boundary_surface(mesh, f.Surface);
  ASSERT_TRUE(extracted) << extracted.message;
  const femorph::SurfaceMesh& s = f.Surface;
  ASSERT_EQ(s.num_triangles(), 6 * 2 * N * N);
  ASSERT_EQ(s.num_points(), 6 * N * N + 2);

  femorph::Segmentation& seg = f.Segmentation;
  seg.regions.resize(6);
  for (int r = 0; r < 6; ++r)
  {
    femorph::Region& region = seg.regions[r];
    region.id = r;
    region.type = static_cast<SurfaceType>(r);
    region.surface = MadeUpSurface(r);
    region.fit_rms = 1e-3 * (r + 1);
    region.fit_max = 2e-3 * (r + 1);
    region.convexity = static_cast<femorph::Convexity>(r % 3);
    for (int n = 0; n < 6; ++n)
    {
      if (n / 2 != r / 2)
      {
        region.neighbors.push_back(n);
        region.continuity.push_back(femorph::Continuity::G0);
      }
    }
  }
  seg.triangle_region.resize(s.num_triangles());
  for (femorph::index_t t = 0; t < s.num_triangles(); ++t)
  {
    const femorph::Vec3 c =
      (s.points[s.triangles[t][0]] + s.points[s.triangles[t][1]] + s.points[s.triangles[t][2]]) / 3;
    int region = -1;
    for (int axis = 0; axis < 3; ++axis)
    {
      if (c[axis] == 0 || c[axis] == 1)
      {
        region = 2 * axis + static_cast<int>(c[axis]);
      }
    }
    ASSERT_GE(region, 0);
    seg.triangle_region[t] = region;
    seg.regions[region].area += s.areas[t];
    ++seg.regions[region].triangle_count;
  }
  seg.vertex_class.resize(s.num_points());
  seg.vertex_curve.assign(s.num_points(), femorph::kInvalidIndex);
  for (femorph::index_t v = 0; v < s.num_points(); ++v)
  {
    int regions[3];
    seg.vertex_class[v] = static_cast<std::int8_t>(PlanesOf(s.points[v].data(), regions));
  }

  // Surface vertex at a grid position (i, j, k) of the cube.
  auto vertexAt = [&s](int i, int j, int k) {
    const femorph::Vec3 p(double(i) / N, double(j) / N, double(k) / N);
    for (femorph::index_t v = 0; v < s.num_points(); ++v)
    {
      if (s.points[v] == p)
      {
        return v;
      }
    }
    ADD_FAILURE() << "no surface vertex at " << i << " " << j << " " << k;
    return femorph::index_t(0);
  };
  // Curves 0-3: the vertical edges, bottom to top.
  for (int e = 0; e < 4; ++e)
  {
    femorph::BoundaryCurve curve;
    curve.id = e;
    curve.type = femorph::CurveType::Line;
    const int i = e % 2, j = e / 2;
    for (int k = 0; k <= N; ++k)
    {
      curve.vertices.push_back(vertexAt(i * N, j * N, k));
    }
    curve.curve.type = curve.type;
    curve.curve.start = femorph::Vec3(i, j, 0);
    curve.curve.end = femorph::Vec3(i, j, 1);
    curve.curve.direction = femorph::Vec3(0, 0, 1);
    curve.region_a = i;     // x = i
    curve.region_b = 2 + j; // y = j
    curve.continuity = femorph::Continuity::G0;
    seg.curves.push_back(curve);
  }
  // Curves 4-5: the loops around the bottom (z = 0) and top (z = 1) faces.
  for (int k = 0; k < 2; ++k)
  {
    femorph::BoundaryCurve curve;
    curve.id = 4 + k;
    curve.type = k ? femorph::CurveType::Circle : femorph::CurveType::Ellipse;
    curve.closed = true;
    for (int i = 0; i < N; ++i)
      curve.vertices.push_back(vertexAt(i, 0, k * N));
    for (int j = 0; j < N; ++j)
      curve.vertices.push_back(vertexAt(N, j, k * N));
    for (int i = N; i > 0; --i)
      curve.vertices.push_back(vertexAt(i, N, k * N));
    for (int j = N; j > 0; --j)
      curve.vertices.push_back(vertexAt(0, j, k * N));
    curve.curve.type = curve.type;
    curve.curve.center = femorph::Vec3(0.5, 0.5, k);
    curve.curve.normal = femorph::Vec3(0, 0, 1);
    curve.curve.direction = femorph::Vec3(1, 0, 0);
    curve.curve.radius = 0.7;
    curve.curve.minor_radius = k ? 0.0 : 0.6;
    curve.region_a = 4 + k;
    curve.region_b = femorph::kInvalidIndex;
    curve.continuity = femorph::Continuity::G1;
    seg.curves.push_back(curve);
  }
  seg.times.sharp_edges = 0.5;
  seg.times.total = 7.25;
}

vtkDataArray* FieldArray(vtkDataSet* data, const char* name)
{
  vtkDataArray* a = data->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << "field data " << name;
  return a;
}

void ExpectTuple(vtkDataArray* a, vtkIdType row, const femorph::Vec3& expected, const char* what)
{
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(a->GetComponent(row, k), expected[k]) << what << " row " << row;
  }
}

void ExpectNaN(vtkDataArray* a, vtkIdType row, const char* what)
{
  for (int k = 0; k < a->GetNumberOfComponents(); ++k)
  {
    EXPECT_TRUE(std::isnan(a->GetComponent(row, k)))
      << what << " row " << row << " is " << a->GetComponent(row, k);
  }
}

// Everything WriteToMesh() writes, checked against the geometry of the cube
// and the hand-built segmentation.
void CheckMeshArrays(vtkUnstructuredGrid* out, const Fixture& f)
{
  const femorph::Segmentation& seg = f.Segmentation;
  vtkDataArray* faceRegion = out->GetCellData()->GetArray(Arrays::FaceRegionName);
  ASSERT_NE(faceRegion, nullptr);
  EXPECT_TRUE(vtkIntArray::SafeDownCast(faceRegion));
  ASSERT_EQ(faceRegion->GetNumberOfComponents(), 4);
  ASSERT_EQ(faceRegion->GetNumberOfTuples(), out->GetNumberOfCells());
  vtkNew<vtkIdList> cell;
  int boundaryFaces = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    out->GetCellPoints(c, cell);
    for (int i = 0; i < 4; ++i)
    {
      vtkIdType face[3];
      for (int k = 0, n = 0; k < 4; ++k)
      {
        if (k != i)
        {
          face[n++] = cell->GetId(k);
        }
      }
      const int expected = FaceRegionOf(out->GetPoints(), face);
      EXPECT_EQ(faceRegion->GetComponent(c, i), expected) << "cell " << c << " face " << i;
      boundaryFaces += expected >= 0;
    }
  }
  EXPECT_EQ(boundaryFaces, f.Surface.num_triangles());

  vtkDataArray* vertexClass = out->GetPointData()->GetArray(Arrays::VertexClassName);
  ASSERT_NE(vertexClass, nullptr);
  EXPECT_TRUE(vtkUnsignedCharArray::SafeDownCast(vertexClass));
  ASSERT_EQ(vertexClass->GetNumberOfTuples(), out->GetNumberOfPoints());
  int classCount[4] = { 0, 0, 0, 0 };
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double p[3];
    out->GetPoint(i, p);
    int regions[3];
    EXPECT_EQ(vertexClass->GetComponent(i, 0), PlanesOf(p, regions)) << "point " << i;
    ++classCount[static_cast<int>(vertexClass->GetComponent(i, 0))];
  }
  EXPECT_EQ(classCount[0], (N - 1) * (N - 1) * (N - 1));
  EXPECT_EQ(classCount[3], 8);
  EXPECT_EQ(classCount[2], 12 * (N - 1));

  vtkDataArray* regionType = FieldArray(out, Arrays::RegionTypeName);
  vtkDataArray* regionParameters = FieldArray(out, Arrays::RegionParametersName);
  vtkDataArray* regionConvexity = FieldArray(out, Arrays::RegionConvexityName);
  ASSERT_TRUE(regionType && regionParameters && regionConvexity);
  EXPECT_TRUE(vtkIntArray::SafeDownCast(regionType));
  EXPECT_TRUE(vtkIntArray::SafeDownCast(regionConvexity));
  EXPECT_TRUE(vtkDoubleArray::SafeDownCast(regionParameters));
  ASSERT_EQ(regionType->GetNumberOfTuples(), 6);
  ASSERT_EQ(regionParameters->GetNumberOfTuples(), 6);
  ASSERT_EQ(regionParameters->GetNumberOfComponents(), femorph::kRegionParameterWidth);
  ASSERT_EQ(regionConvexity->GetNumberOfTuples(), 6);
  for (int r = 0; r < 6; ++r)
  {
    const femorph::Region& region = seg.regions[r];
    EXPECT_EQ(regionType->GetComponent(r, 0), r);
    EXPECT_EQ(regionConvexity->GetComponent(r, 0), r % 3);
    // The documented layout, entry by entry.
    const femorph::SurfacePrimitive& s = region.surface;
    const double expected[femorph::kRegionParameterWidth] = { s.point.x(), s.point.y(),
      s.point.z(), s.axis.x(), s.axis.y(), s.axis.z(), s.radius, s.minor_radius, s.half_angle,
      double(r % 3), region.fit_rms, region.area };
    for (int k = 0; k < femorph::kRegionParameterWidth; ++k)
    {
      EXPECT_EQ(regionParameters->GetComponent(r, k), expected[k]) << "region " << r << " " << k;
    }
  }

  vtkDataArray* curveType = FieldArray(out, Arrays::CurveTypeName);
  vtkDataArray* curveParameters = FieldArray(out, Arrays::CurveParametersName);
  vtkDataArray* curveClosed = FieldArray(out, Arrays::CurveClosedName);
  vtkDataArray* curveVertices = FieldArray(out, Arrays::CurveVerticesName);
  vtkDataArray* curveOffsets = FieldArray(out, Arrays::CurveOffsetsName);
  ASSERT_TRUE(curveType && curveParameters && curveClosed && curveVertices && curveOffsets);
  EXPECT_TRUE(vtkIdTypeArray::SafeDownCast(curveVertices));
  EXPECT_TRUE(vtkIdTypeArray::SafeDownCast(curveOffsets));
  ASSERT_EQ(curveType->GetNumberOfTuples(), 6);
  ASSERT_EQ(curveParameters->GetNumberOfComponents(), femorph::kCurveParameterWidth);
  ASSERT_EQ(curveOffsets->GetNumberOfTuples(), 7);
  ASSERT_EQ(curveVertices->GetNumberOfTuples(), 4 * (N + 1) + 2 * 4 * N);
  for (int c = 0; c < 6; ++c)
  {
    const femorph::BoundaryCurve& curve = seg.curves[c];
    EXPECT_EQ(curveType->GetComponent(c, 0), static_cast<int>(curve.type));
    EXPECT_EQ(curveClosed->GetComponent(c, 0), c >= 4 ? 1 : 0);
    const femorph::CurvePrimitive& p = curve.curve;
    const double expected[femorph::kCurveParameterWidth] = { p.center.x(), p.center.y(),
      p.center.z(), p.normal.x(), p.normal.y(), p.normal.z(), p.direction.x(), p.direction.y(),
      p.direction.z(), p.radius, p.minor_radius, p.start.x(), p.start.y(), p.start.z(), p.end.x(),
      p.end.y(), p.end.z(), double(curve.region_a), double(curve.region_b),
      double(static_cast<int>(curve.continuity)) };
    for (int k = 0; k < femorph::kCurveParameterWidth; ++k)
    {
      EXPECT_EQ(curveParameters->GetComponent(c, k), expected[k]) << "curve " << c << " " << k;
    }
    // The curve's points, in order, as mesh points at the right positions.
    const vtkIdType begin = static_cast<vtkIdType>(curveOffsets->GetComponent(c, 0));
    const vtkIdType end = static_cast<vtkIdType>(curveOffsets->GetComponent(c + 1, 0));
    ASSERT_EQ(end - begin, static_cast<vtkIdType>(curve.vertices.size()));
    for (vtkIdType k = begin; k < end; ++k)
    {
      const vtkIdType id = static_cast<vtkIdType>(curveVertices->GetComponent(k, 0));
      double p3[3];
      out->GetPoint(id, p3);
      const femorph::Vec3& expectedPoint = f.Surface.points[curve.vertices[k - begin]];
      EXPECT_EQ(femorph::Vec3(p3[0], p3[1], p3[2]), expectedPoint) << "curve " << c;
    }
  }
  EXPECT_EQ(curveOffsets->GetComponent(0, 0), 0);

  vtkDataArray* times = FieldArray(out, Arrays::SegmentationTimesName);
  ASSERT_NE(times, nullptr);
  ASSERT_EQ(times->GetNumberOfTuples(), 1);
  ASSERT_EQ(times->GetNumberOfComponents(), 12);
  EXPECT_STREQ(times->GetComponentName(0), "SharpEdges");
  EXPECT_STREQ(times->GetComponentName(11), "Total");
  EXPECT_EQ(times->GetComponent(0, 0), 0.5);
  EXPECT_EQ(times->GetComponent(0, 11), 7.25);
}

// ReadFromMesh() returns what was written.
void CheckReadBack(vtkUnstructuredGrid* grid, const Fixture& f)
{
  Arrays::MeshSegmentation read;
  const femorph::Status status = Arrays::ReadFromMesh(grid, read);
  ASSERT_TRUE(status) << status.message;
  vtkDataArray* faceRegion = grid->GetCellData()->GetArray(Arrays::FaceRegionName);
  ASSERT_EQ(read.FaceRegions.size(), static_cast<std::size_t>(grid->GetNumberOfCells()));
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    for (int i = 0; i < 4; ++i)
    {
      EXPECT_EQ(read.FaceRegions[c][i], faceRegion->GetComponent(c, i));
    }
  }
  ASSERT_EQ(read.VertexClasses.size(), static_cast<std::size_t>(grid->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    int regions[3];
    EXPECT_EQ(read.VertexClasses[i], PlanesOf(p, regions));
  }
  ASSERT_EQ(read.RegionTypes.size(), 6u);
  ASSERT_EQ(read.RegionSurfaces.size(), 6u);
  for (int r = 0; r < 6; ++r)
  {
    const femorph::Region& region = f.Segmentation.regions[r];
    EXPECT_EQ(read.RegionTypes[r], region.type);
    EXPECT_EQ(read.RegionConvexity[r], region.convexity);
    const femorph::SurfacePrimitive& got = read.RegionSurfaces[r];
    EXPECT_EQ(got.type, region.type);
    EXPECT_EQ(got.point, region.surface.point);
    EXPECT_EQ(got.axis, region.surface.axis);
    EXPECT_EQ(got.radius, region.surface.radius);
    EXPECT_EQ(got.minor_radius, region.surface.minor_radius);
    EXPECT_EQ(got.half_angle, region.surface.half_angle);
    EXPECT_EQ(read.RegionParameters[r], femorph::pack_region_parameters(region));
  }
  ASSERT_EQ(read.CurveTypes.size(), 6u);
  for (int c = 0; c < 6; ++c)
  {
    const femorph::BoundaryCurve& curve = f.Segmentation.curves[c];
    EXPECT_EQ(read.CurveTypes[c], curve.type);
    EXPECT_EQ(read.CurveClosed[c], curve.closed);
    EXPECT_EQ(read.CurveParameters[c], femorph::pack_curve_parameters(curve));
    ASSERT_EQ(read.CurveVertices[c].size(), curve.vertices.size());
    for (std::size_t k = 0; k < curve.vertices.size(); ++k)
    {
      EXPECT_EQ(read.CurveVertices[c][k], f.Surface.source_vertex[curve.vertices[k]]);
    }
  }
}

class SegmentationArrays : public ::testing::TestWithParam<bool>
{
};

} // namespace

TEST(SegmentationPacking, RowsFollowTheDocumentedLayout)
{
  femorph::Region region;
  region.type = SurfaceType::Torus;
  region.surface = MadeUpSurface(4);
  region.convexity = femorph::Convexity::Concave;
  region.fit_rms = 0.125;
  region.area = 42.5;
  const auto row = femorph::pack_region_parameters(region);
  const double expected[] = { 4.5, -5, 2.5, 0, 1, 0, 15, 3, 0, 2, 0.125, 42.5 };
  for (int k = 0; k < femorph::kRegionParameterWidth; ++k)
  {
    EXPECT_EQ(row[k], expected[k]) << k;
  }
  // Every type comes back as it was packed.
  for (int r = 0; r < 6; ++r)
  {
    femorph::Region any;
    any.type = static_cast<SurfaceType>(r);
    any.surface = MadeUpSurface(r);
    any.surface.half_angle = 0.25 * r; // also where it does not apply
    const auto packed = femorph::pack_region_parameters(any);
    const femorph::SurfacePrimitive back = femorph::unpack_region_surface(any.type, packed.data());
    EXPECT_EQ(back.type, any.type);
    EXPECT_EQ(back.point, any.surface.point);
    EXPECT_EQ(back.axis, any.surface.axis);
    EXPECT_EQ(back.radius, any.surface.radius);
    EXPECT_EQ(back.minor_radius, any.surface.minor_radius);
    EXPECT_EQ(back.half_angle, any.surface.half_angle);
  }
  EXPECT_EQ(femorph::unpack_region_surface(SurfaceType::Plane, nullptr).type, SurfaceType::Plane);

  femorph::BoundaryCurve curve;
  curve.curve.center = femorph::Vec3(1, 2, 3);
  curve.curve.normal = femorph::Vec3(0, 0, 1);
  curve.curve.direction = femorph::Vec3(1, 0, 0);
  curve.curve.radius = 4;
  curve.curve.minor_radius = 5;
  curve.curve.start = femorph::Vec3(6, 7, 8);
  curve.curve.end = femorph::Vec3(9, 10, 11);
  curve.region_a = 12;
  curve.region_b = femorph::kInvalidIndex;
  curve.continuity = femorph::Continuity::G1;
  const auto c = femorph::pack_curve_parameters(curve);
  const double expectedCurve[] = { 1, 2, 3, 0, 0, 1, 1, 0, 0, 4, 5, 6, 7, 8, 9, 10, 11, 12, -1,
    1 };
  for (int k = 0; k < femorph::kCurveParameterWidth; ++k)
  {
    EXPECT_EQ(c[k], expectedCurve[k]) << k;
  }
}

TEST_P(SegmentationArrays, MeshArraysAndReadBack)
{
  Fixture f;
  MakeFixture(GetParam(), f);
  if (HasFatalFailure())
  {
    return;
  }
  vtkNew<vtkUnstructuredGrid> out;
  out->ShallowCopy(f.Input);
  const femorph::Status status = Arrays::WriteToMesh(f.Surface, f.Segmentation, out);
  ASSERT_TRUE(status) << status.message;
  CheckMeshArrays(out, f);
  CheckReadBack(out, f);
  // The input is not touched by writing onto its shallow copy.
  EXPECT_EQ(f.Input->GetCellData()->GetArray(Arrays::FaceRegionName), nullptr);
  EXPECT_EQ(f.Input->GetFieldData()->GetNumberOfArrays(), 0);

  // Writing again replaces the arrays instead of adding more.
  const int arrays = out->GetFieldData()->GetNumberOfArrays();
  ASSERT_TRUE(Arrays::WriteToMesh(f.Surface, f.Segmentation, out));
  EXPECT_EQ(out->GetFieldData()->GetNumberOfArrays(), arrays);
  EXPECT_EQ(out->GetCellData()->GetNumberOfArrays(), 1);
  EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 2); // Temperature, VertexClass

  // Through a .vtu file, as between ParaView sessions.
  const std::string path = (std::filesystem::temp_directory_path() /
    ("femorph_segmentation_arrays_" + std::to_string(GetParam()) + ".vtu"))
                             .string();
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(out);
  ASSERT_EQ(writer->Write(), 1);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  std::remove(path.c_str());
  CheckMeshArrays(reader->GetOutput(), f);
  CheckReadBack(reader->GetOutput(), f);
}

TEST_P(SegmentationArrays, SurfaceWithRegionsAndPolylines)
{
  Fixture f;
  MakeFixture(GetParam(), f);
  if (HasFatalFailure())
  {
    return;
  }
  const femorph::SurfaceMesh& s = f.Surface;
  const femorph::Segmentation& seg = f.Segmentation;
  vtkNew<vtkPolyData> surface;
  const femorph::Status status = Arrays::WriteSurface(s, seg, f.Input, surface);
  ASSERT_TRUE(status) << status.message;

  ASSERT_EQ(surface->GetNumberOfPoints(), s.num_points());
  ASSERT_EQ(surface->GetNumberOfPolys(), s.num_triangles());
  ASSERT_EQ(surface->GetNumberOfLines(), 6);
  ASSERT_EQ(surface->GetNumberOfCells(), 6 + s.num_triangles());
  vtkCellData* cd = surface->GetCellData();
  vtkDataArray* regionId = cd->GetArray(Arrays::RegionIdName);
  vtkDataArray* regionType = cd->GetArray(Arrays::RegionTypeName);
  vtkDataArray* curveId = cd->GetArray(Arrays::CurveIdName);
  vtkDataArray* curveType = cd->GetArray(Arrays::CurveTypeName);
  ASSERT_TRUE(regionId && regionType && curveId && curveType);
  EXPECT_STREQ(cd->GetScalars()->GetName(), Arrays::RegionIdName);

  // Lines first (vtkPolyData's cell order): the curves as polylines; a loop
  // repeats its first point.
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < 6; ++c)
  {
    const femorph::BoundaryCurve& curve = seg.curves[c];
    EXPECT_EQ(surface->GetCellType(c), VTK_POLY_LINE);
    surface->GetCellPoints(c, ids);
    const std::size_t expectedSize = curve.vertices.size() + (curve.closed ? 1 : 0);
    ASSERT_EQ(static_cast<std::size_t>(ids->GetNumberOfIds()), expectedSize);
    for (std::size_t k = 0; k < expectedSize; ++k)
    {
      EXPECT_EQ(ids->GetId(k), curve.vertices[k % curve.vertices.size()]);
    }
    EXPECT_EQ(regionId->GetComponent(c, 0), -1);
    EXPECT_EQ(regionType->GetComponent(c, 0), -1);
    EXPECT_EQ(curveId->GetComponent(c, 0), c);
    EXPECT_EQ(curveType->GetComponent(c, 0), static_cast<int>(curve.type));
  }
  // Then the triangles, in the surface's order.
  for (femorph::index_t t = 0; t < s.num_triangles(); ++t)
  {
    const vtkIdType cell = 6 + t;
    EXPECT_EQ(surface->GetCellType(cell), VTK_TRIANGLE);
    surface->GetCellPoints(cell, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 3);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(ids->GetId(k), s.triangles[t][k]);
    }
    EXPECT_EQ(regionId->GetComponent(cell, 0), seg.triangle_region[t]);
    EXPECT_EQ(regionType->GetComponent(cell, 0), seg.triangle_region[t]); // type r = region r
    EXPECT_EQ(curveId->GetComponent(cell, 0), -1);
    EXPECT_EQ(curveType->GetComponent(cell, 0), -1);
  }

  // Points: the surface vertices, their mesh point, class and the mesh's data.
  vtkPointData* pd = surface->GetPointData();
  vtkDataArray* meshPoint = pd->GetArray(Arrays::MeshPointIdName);
  vtkDataArray* vertexClass = pd->GetArray(Arrays::VertexClassName);
  vtkDataArray* temperature = pd->GetArray("Temperature");
  ASSERT_TRUE(meshPoint && vertexClass && temperature);
  EXPECT_TRUE(vtkIdTypeArray::SafeDownCast(meshPoint));
  for (vtkIdType v = 0; v < surface->GetNumberOfPoints(); ++v)
  {
    const vtkIdType id = static_cast<vtkIdType>(meshPoint->GetComponent(v, 0));
    double a[3], b[3];
    surface->GetPoint(v, a);
    f.Input->GetPoint(id, b);
    EXPECT_TRUE(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) << "vertex " << v;
    EXPECT_EQ(vertexClass->GetComponent(v, 0), seg.vertex_class[v]);
    EXPECT_EQ(temperature->GetComponent(v, 0), 10.0 + 0.25 * id);
  }

  // Without a mesh: no copied point data, the rest the same.
  vtkNew<vtkPolyData> bare;
  ASSERT_TRUE(Arrays::WriteSurface(s, seg, nullptr, bare));
  EXPECT_EQ(bare->GetPointData()->GetNumberOfArrays(), 2);
  EXPECT_EQ(bare->GetNumberOfCells(), surface->GetNumberOfCells());
}

TEST_P(SegmentationArrays, RegionTable)
{
  Fixture f;
  MakeFixture(GetParam(), f);
  if (HasFatalFailure())
  {
    return;
  }
  vtkNew<vtkTable> table;
  ASSERT_TRUE(Arrays::WriteRegionTable(f.Segmentation, table));

  // Exactly the columns of docs/ARCHITECTURE.md, in order, so scripts can rely on them.
  const std::vector<std::string> design = { "RegionId", "TypeName", "Radius", "MajorRadius",
    "MinorRadius", "HalfAngle", "Axis", "Center", "Apex", "Normal", "Point", "Area", "Convexity",
    "TriangleCount", "FitResidual", "Neighbors" };
  EXPECT_EQ(Arrays::RegionTableColumns(), design);
  ASSERT_EQ(table->GetNumberOfColumns(), static_cast<vtkIdType>(design.size()));
  for (std::size_t k = 0; k < design.size(); ++k)
  {
    EXPECT_STREQ(table->GetColumnName(static_cast<vtkIdType>(k)), design[k].c_str());
  }
  ASSERT_EQ(table->GetNumberOfRows(), 6);
  auto number = [&](const char* name) {
    vtkDataArray* a = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
    EXPECT_NE(a, nullptr) << name;
    return a;
  };
  auto text = [&](const char* name) {
    vtkStringArray* a = vtkStringArray::SafeDownCast(table->GetColumnByName(name));
    EXPECT_NE(a, nullptr) << name << " is not a string column";
    return a;
  };
  for (const char* name : { "Axis", "Center", "Apex", "Normal", "Point" })
  {
    EXPECT_EQ(number(name)->GetNumberOfComponents(), 3) << name;
  }
  const char* typeNames[] = { "plane", "cylinder", "cone", "sphere", "torus", "unknown" };
  const char* convexity[] = { "", "convex", "concave" };
  const char* scalarColumns[] = { "Radius", "MajorRadius", "MinorRadius", "HalfAngle" };
  const char* vectorColumns[] = { "Axis", "Center", "Apex", "Normal", "Point" };
  for (int r = 0; r < 6; ++r)
  {
    const femorph::Region& region = f.Segmentation.regions[r];
    const femorph::SurfacePrimitive& s = region.surface;
    EXPECT_EQ(number("RegionId")->GetComponent(r, 0), r);
    EXPECT_EQ(text("TypeName")->GetValue(r), typeNames[r]);
    EXPECT_NEAR(number("Area")->GetComponent(r, 0), 1.0, Tol); // a unit face
    EXPECT_EQ(number("TriangleCount")->GetComponent(r, 0), 2 * N * N);
    EXPECT_EQ(text("Convexity")->GetValue(r), convexity[r % 3]);
    // The neighbours: every face but itself and the opposite one.
    std::string neighbors;
    for (int n = 0; n < 6; ++n)
    {
      if (n / 2 != r / 2)
      {
        neighbors += (neighbors.empty() ? "" : " ") + std::to_string(n);
      }
    }
    EXPECT_EQ(text("Neighbors")->GetValue(r), neighbors);
    if (r == 5)
    {
      ExpectNaN(number("FitResidual"), r, "FitResidual of unknown");
    }
    else
    {
      EXPECT_EQ(number("FitResidual")->GetComponent(r, 0), region.fit_rms);
    }

    // Which columns apply to which type; NaN in the others.
    std::set<std::string> applies;
    switch (region.type)
    {
      case SurfaceType::Plane:
        ExpectTuple(number("Normal"), r, s.axis, "Normal");
        ExpectTuple(number("Point"), r, s.point, "Point");
        applies = { "Normal", "Point" };
        break;
      case SurfaceType::Cylinder:
        EXPECT_EQ(number("Radius")->GetComponent(r, 0), 12);
        ExpectTuple(number("Axis"), r, s.axis, "Axis");
        ExpectTuple(number("Center"), r, s.point, "Center");
        applies = { "Radius", "Axis", "Center" };
        break;
      case SurfaceType::Cone:
        EXPECT_NEAR(number("HalfAngle")->GetComponent(r, 0), 45, Tol); // degrees
        ExpectTuple(number("Axis"), r, s.axis, "Axis");
        ExpectTuple(number("Apex"), r, s.point, "Apex");
        applies = { "HalfAngle", "Axis", "Apex" };
        break;
      case SurfaceType::Sphere:
        EXPECT_EQ(number("Radius")->GetComponent(r, 0), 6.5);
        ExpectTuple(number("Center"), r, s.point, "Center");
        applies = { "Radius", "Center" };
        break;
      case SurfaceType::Torus:
        EXPECT_EQ(number("MajorRadius")->GetComponent(r, 0), 15);
        EXPECT_EQ(number("MinorRadius")->GetComponent(r, 0), 3);
        ExpectTuple(number("Axis"), r, s.axis, "Axis");
        ExpectTuple(number("Center"), r, s.point, "Center");
        applies = { "MajorRadius", "MinorRadius", "Axis", "Center" };
        break;
      default: break;
    }
    for (const char* name : scalarColumns)
    {
      if (!applies.count(name))
      {
        ExpectNaN(number(name), r, name);
      }
    }
    for (const char* name : vectorColumns)
    {
      if (!applies.count(name))
      {
        ExpectNaN(number(name), r, name);
      }
    }
  }

  // No regions: the columns without rows.
  vtkNew<vtkTable> empty;
  ASSERT_TRUE(Arrays::WriteRegionTable(femorph::Segmentation(), empty));
  EXPECT_EQ(empty->GetNumberOfColumns(), static_cast<vtkIdType>(design.size()));
  EXPECT_EQ(empty->GetNumberOfRows(), 0);
}

INSTANTIATE_TEST_SUITE_P(Orientation, SegmentationArrays, ::testing::Values(false, true),
  [](const ::testing::TestParamInfo<bool>& info) { return info.param ? "Flipped" : "Positive"; });

// The writers refuse a segmentation that does not fit the surface, naming
// the problem, and write nothing.
TEST(SegmentationArraysRefusals, InconsistentSegmentation)
{
  Fixture f;
  MakeFixture(false, f);
  if (HasFatalFailure())
  {
    return;
  }
  struct Case
  {
    const char* Expected;
    std::function<void(Fixture&)> Break;
  };
  const std::vector<Case> cases = {
    { "triangle regions for", [](Fixture& g) { g.Segmentation.triangle_region.pop_back(); } },
    { "has region 6 of 6", [](Fixture& g) { g.Segmentation.triangle_region[3] = 6; } },
    { "has region -2", [](Fixture& g) { g.Segmentation.triangle_region[0] = -2; } },
    { "vertex classes for", [](Fixture& g) { g.Segmentation.vertex_class.clear(); } },
    { "has class 4", [](Fixture& g) { g.Segmentation.vertex_class[1] = 4; } },
    { "has neighbour 9", [](Fixture& g) { g.Segmentation.regions[0].neighbors.push_back(9); } },
    { "has type code 6",
      [](Fixture& g) { g.Segmentation.regions[2].type = static_cast<SurfaceType>(6); } },
    { "curve 1 has vertex", [](Fixture& g) { g.Segmentation.curves[1].vertices.push_back(1000); } },
    { "curve 2 has no vertices", [](Fixture& g) { g.Segmentation.curves[2].vertices.clear(); } },
    { "separates regions 7", [](Fixture& g) { g.Segmentation.curves[0].region_a = 7; } },
    { "mesh points and faces", [](Fixture& g) { g.Surface.source_vertex.clear(); } },
    { "comes from cell", [](Fixture& g) { g.Surface.source_face[0] = 4 * 100000; } },
    { "is not a face of cell", [](Fixture& g) { std::swap(g.Surface.source_face[0], g.Surface.source_face[20]); } },
  };
  for (const Case& c : cases)
  {
    Fixture g = f;
    c.Break(g);
    vtkNew<vtkUnstructuredGrid> mesh;
    mesh->ShallowCopy(g.Input);
    const femorph::Status status = Arrays::WriteToMesh(g.Surface, g.Segmentation, mesh);
    ASSERT_FALSE(status) << c.Expected;
    EXPECT_NE(status.message.find(c.Expected), std::string::npos) << status.message;
    EXPECT_EQ(mesh->GetCellData()->GetArray(Arrays::FaceRegionName), nullptr) << c.Expected;
    EXPECT_EQ(mesh->GetFieldData()->GetNumberOfArrays(), 0) << c.Expected;
    vtkNew<vtkPolyData> surface;
    EXPECT_FALSE(Arrays::WriteSurface(g.Surface, g.Segmentation, g.Input, surface)) << c.Expected;
  }
}

// The reader names the missing or malformed array and asks for FEMorph
// Segment; what it does not need (VertexClass) may be missing.
TEST(SegmentationArraysRefusals, ReaderNamesTheProblem)
{
  Fixture f;
  MakeFixture(false, f);
  if (HasFatalFailure())
  {
    return;
  }
  vtkNew<vtkUnstructuredGrid> good;
  good->ShallowCopy(f.Input);
  ASSERT_TRUE(Arrays::WriteToMesh(f.Surface, f.Segmentation, good));

  Arrays::MeshSegmentation read;
  femorph::Status status = Arrays::ReadFromMesh(f.Input, read);
  ASSERT_FALSE(status);
  EXPECT_NE(status.message.find("the input has no field array RegionType"),
    std::string::npos)
    << status.message;
  EXPECT_NE(status.message.find("Run FEMorph Segment"), std::string::npos) << status.message;
  EXPECT_TRUE(read.RegionTypes.empty());

  auto intArray = [](const char* name, int components, std::vector<double> values) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    for (double v : values)
    {
      a->InsertNextValue(v);
    }
    return a;
  };
  struct Case
  {
    const char* Expected;
    std::function<void(vtkUnstructuredGrid*)> Break;
  };
  const std::vector<Case> cases = {
    { "no cell array FaceRegion",
      [](vtkUnstructuredGrid* g) { g->GetCellData()->RemoveArray(Arrays::FaceRegionName); } },
    { "FaceRegion of the input has 1 components instead of 4",
      [&](vtkUnstructuredGrid* g) {
        auto a = intArray(Arrays::FaceRegionName, 1, {});
        a->SetNumberOfTuples(g->GetNumberOfCells());
        a->Fill(-1);
        g->GetCellData()->AddArray(a);
      } },
    { "expected a whole number in [-1, 5]",
      [](vtkUnstructuredGrid* g) {
        g->GetCellData()->GetArray(Arrays::FaceRegionName)->SetComponent(3, 2, 6);
      } },
    { "FaceRegion of the input has the value nan at 0, component 0",
      [](vtkUnstructuredGrid* g) {
        // Any numeric type is read; a double array can hold a NaN.
        vtkNew<vtkDoubleArray> a;
        a->DeepCopy(g->GetCellData()->GetArray(Arrays::FaceRegionName));
        a->SetComponent(0, 0, std::nan(""));
        g->GetCellData()->AddArray(a);
      } },
    { "FaceRegion of the input has the value 0.5 at 2, component 1",
      [](vtkUnstructuredGrid* g) {
        vtkNew<vtkDoubleArray> a;
        a->DeepCopy(g->GetCellData()->GetArray(Arrays::FaceRegionName));
        a->SetComponent(2, 1, 0.5);
        g->GetCellData()->AddArray(a);
      } },
    { "RegionParameters of the input has 3 components instead of 12",
      [&](vtkUnstructuredGrid* g) {
        g->GetFieldData()->AddArray(intArray(Arrays::RegionParametersName, 3, std::vector<double>(18, 0.0)));
      } },
    { "RegionConvexity of the input has 2 values instead of 6",
      [&](vtkUnstructuredGrid* g) {
        g->GetFieldData()->AddArray(intArray(Arrays::RegionConvexityName, 1, { 0, 1 }));
      } },
    { "RegionType of the input has the value 9",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::RegionTypeName)->SetComponent(1, 0, 9);
      } },
    { "RegionType of the input is not numeric",
      [](vtkUnstructuredGrid* g) {
        vtkNew<vtkStringArray> s;
        s->SetName(Arrays::RegionTypeName);
        s->InsertNextValue("plane");
        g->GetFieldData()->AddArray(s);
      } },
    { "no field array CurveVertices",
      [](vtkUnstructuredGrid* g) { g->GetFieldData()->RemoveArray(Arrays::CurveVerticesName); } },
    { "CurveOffsets of the input does not span",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveOffsetsName)->SetComponent(6, 0, 3);
      } },
    { "CurveOffsets of the input decreases at curve 1",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveOffsetsName)->SetComponent(1, 0, 10);
      } },
    { "CurveVertices of the input has the value",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveVerticesName)->SetComponent(0, 0, 1e6);
      } },
    { "VertexClass of the input has 1 values instead of",
      [&](vtkUnstructuredGrid* g) {
        g->GetPointData()->AddArray(intArray(Arrays::VertexClassName, 1, { 1 }));
      } },
    { "FaceRegion of the input has the value 2.14748e+09 at 0",
      [](vtkUnstructuredGrid* g) {
        g->GetCellData()->GetArray(Arrays::FaceRegionName)->SetComponent(0, 0, VTK_INT_MAX);
      } },
    { "FaceRegion of the input has the value -2 at 1, component 3",
      [](vtkUnstructuredGrid* g) {
        g->GetCellData()->GetArray(Arrays::FaceRegionName)->SetComponent(1, 3, -2);
      } },
    { "FaceRegion of the input has 3 values instead of",
      [](vtkUnstructuredGrid* g) {
        g->GetCellData()->GetArray(Arrays::FaceRegionName)->SetNumberOfTuples(3);
      } },
    { "RegionParameters of the input has a NaN or infinite value at 2, component 6",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::RegionParametersName)->SetComponent(2, 6, std::nan(""));
      } },
    { "CurveParameters of the input has a NaN or infinite value at 1, component 9",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveParametersName)
          ->SetComponent(1, 9, std::numeric_limits<double>::infinity());
      } },
    { "CurveParameters names regions 6 and",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveParametersName)->SetComponent(0, 17, 6);
      } },
    { "(continuity 0.5)",
      [](vtkUnstructuredGrid* g) {
        g->GetFieldData()->GetArray(Arrays::CurveParametersName)->SetComponent(0, 19, 0.5);
      } },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkUnstructuredGrid> broken;
    broken->DeepCopy(good);
    c.Break(broken);
    status = Arrays::ReadFromMesh(broken, read);
    ASSERT_FALSE(status) << c.Expected;
    EXPECT_NE(status.message.find(c.Expected), std::string::npos) << status.message;
    EXPECT_TRUE(read.FaceRegions.empty() && read.RegionTypes.empty()) << c.Expected;
  }

  // VertexClass is optional.
  vtkNew<vtkUnstructuredGrid> noClasses;
  noClasses->DeepCopy(good);
  noClasses->GetPointData()->RemoveArray(Arrays::VertexClassName);
  status = Arrays::ReadFromMesh(noClasses, read);
  ASSERT_TRUE(status) << status.message;
  EXPECT_TRUE(read.VertexClasses.empty());
  EXPECT_EQ(read.RegionTypes.size(), 6u);
  EXPECT_FALSE(Arrays::ReadFromMesh(nullptr, read));

  // Whether any segmentation array is there decides "absent" from
  // "malformed".
  EXPECT_TRUE(Arrays::HasSegmentation(good));
  EXPECT_FALSE(Arrays::HasSegmentation(f.Input));
  vtkNew<vtkUnstructuredGrid> onlyFaceRegion;
  onlyFaceRegion->ShallowCopy(f.Input);
  onlyFaceRegion->GetCellData()->AddArray(good->GetCellData()->GetArray(Arrays::FaceRegionName));
  EXPECT_TRUE(Arrays::HasSegmentation(onlyFaceRegion));
  EXPECT_FALSE(Arrays::HasSegmentation(nullptr));
}

// The curves read back whole: the rows unpacked (regions, continuity, fit)
// with their vertices and closedness.
TEST(SegmentationArraysRead, UnpacksTheCurves)
{
  Fixture f;
  MakeFixture(false, f);
  if (HasFatalFailure())
  {
    return;
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->ShallowCopy(f.Input);
  ASSERT_TRUE(Arrays::WriteToMesh(f.Surface, f.Segmentation, grid));
  Arrays::MeshSegmentation read;
  ASSERT_TRUE(Arrays::ReadFromMesh(grid, read));
  ASSERT_EQ(read.Curves.size(), f.Segmentation.curves.size());
  ASSERT_FALSE(read.Curves.empty());
  for (std::size_t c = 0; c < read.Curves.size(); ++c)
  {
    const femorph::BoundaryCurve& in = f.Segmentation.curves[c];
    const femorph::BoundaryCurve& out = read.Curves[c];
    EXPECT_EQ(out.type, in.type);
    EXPECT_EQ(out.curve.type, in.type);
    EXPECT_EQ(out.region_a, in.region_a);
    EXPECT_EQ(out.region_b, in.region_b);
    EXPECT_EQ(out.continuity, in.continuity);
    EXPECT_EQ(out.closed, in.closed);
    EXPECT_EQ(femorph::pack_curve_parameters(out), femorph::pack_curve_parameters(in));
    ASSERT_EQ(out.vertices.size(), in.vertices.size());
    for (std::size_t i = 0; i < in.vertices.size(); ++i)
    {
      EXPECT_EQ(out.vertices[i], f.Surface.source_vertex[in.vertices[i]]);
    }
  }
}
