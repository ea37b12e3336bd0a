// vtkFEMorphMeshConversion: vtkUnstructuredGrid <-> femorph::TetMesh.
// Round trips keep points, cells and every array; an edge split interpolates
// point data linearly and copies the parent's cell data to the children; bad
// input fails with a message naming the problem and leaves the input as it was.
#include "filters_test_utils.h"
#include "vtkFEMorphMeshConversion.h"

#include "mesh/tet_mesh.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>

using femorph_test::MakeGrid;
using femorph_test::MakeTwoTets;
using Conversion = vtkFEMorphMeshConversion;

namespace
{

// Point data Temperature (double, x + 2y + 3z), Label (int, 10 * id); cell
// data Material (int, 7 + id) and Stress (double, 3 components); field data
// Note (string).
void AddArrays(vtkUnstructuredGrid* grid)
{
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  vtkNew<vtkIntArray> label;
  label->SetName("Label");
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    temperature->InsertNextValue(p[0] + 2 * p[1] + 3 * p[2]);
    label->InsertNextValue(static_cast<int>(10 * i));
  }
  grid->GetPointData()->AddArray(temperature);
  grid->GetPointData()->AddArray(label);

  vtkNew<vtkIntArray> material;
  material->SetName("Material");
  vtkNew<vtkDoubleArray> stress;
  stress->SetName("Stress");
  stress->SetNumberOfComponents(3);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    material->InsertNextValue(static_cast<int>(7 + c));
    stress->InsertNextTuple3(c, 2.0 * c, -1.0 * c);
  }
  grid->GetCellData()->AddArray(material);
  grid->GetCellData()->AddArray(stress);

  vtkNew<vtkStringArray> note;
  note->SetName("Note");
  note->InsertNextValue("hand-built");
  grid->GetFieldData()->AddArray(note);
}

// Converts `input` to the core and back without edits.
vtkSmartPointer<vtkUnstructuredGrid> RoundTrip(
  vtkUnstructuredGrid* input, femorph::CompactMesh* compactOut = nullptr)
{
  femorph::TetMesh mesh;
  std::vector<std::string> warnings;
  const femorph::Status status =
    Conversion::ToTetMesh(input, "Test", {}, mesh, nullptr, &warnings);
  EXPECT_TRUE(status.ok) << status.message;
  EXPECT_TRUE(warnings.empty());
  femorph::CompactMesh compact = mesh.compact();
  auto output = vtkSmartPointer<vtkUnstructuredGrid>::New();
  Conversion::FromCompactMesh(compact, input, output);
  if (compactOut)
  {
    *compactOut = std::move(compact);
  }
  return output;
}

// Every output point and cell equals the input one it comes from (through
// vertex_map and tet_origin, which need not be the identity), with every
// input array; and nothing else but FEMorph's own arrays was added.
void ExpectSameMesh(
  vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, const femorph::CompactMesh& compact)
{
  ASSERT_EQ(output->GetNumberOfPoints(), input->GetNumberOfPoints());
  ASSERT_EQ(output->GetNumberOfCells(), input->GetNumberOfCells());
  ASSERT_EQ(static_cast<vtkIdType>(compact.vertex_map.size()), input->GetNumberOfPoints());

  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    const vtkIdType o = compact.vertex_map[i];
    ASSERT_GE(o, 0);
    double p[3], q[3];
    input->GetPoint(i, p);
    output->GetPoint(o, q);
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(p[k], q[k]);
    }
    vtkPointData* inPD = input->GetPointData();
    for (int a = 0; a < inPD->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* in = inPD->GetArray(a);
      vtkDataArray* out = output->GetPointData()->GetArray(in->GetName());
      ASSERT_NE(out, nullptr) << in->GetName();
      EXPECT_EQ(out->GetDataType(), in->GetDataType()) << in->GetName();
      for (int k = 0; k < in->GetNumberOfComponents(); ++k)
      {
        EXPECT_EQ(out->GetComponent(o, k), in->GetComponent(i, k)) << in->GetName();
      }
    }
  }

  for (vtkIdType t = 0; t < output->GetNumberOfCells(); ++t)
  {
    EXPECT_EQ(output->GetCellType(t), VTK_TETRA);
    const vtkIdType origin = compact.tet_origin[t];
    ASSERT_GE(origin, 0);
    vtkNew<vtkIdList> in, out;
    input->GetCellPoints(origin, in);
    output->GetCellPoints(t, out);
    // The same vertices in the same cyclic orientation: positive input tets
    // are not reordered in a way that changes the sign.
    std::set<vtkIdType> inSet, outSet;
    for (int k = 0; k < 4; ++k)
    {
      inSet.insert(compact.vertex_map[in->GetId(k)]);
      outSet.insert(out->GetId(k));
    }
    EXPECT_EQ(inSet, outSet);
    vtkCellData* inCD = input->GetCellData();
    for (int a = 0; a < inCD->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* inArray = inCD->GetArray(a);
      if (std::string(inArray->GetName()) == Conversion::FaceRegionName)
      {
        continue; // recomputed: checked by FaceRegionPassesThrough
      }
      vtkDataArray* outArray = output->GetCellData()->GetArray(inArray->GetName());
      ASSERT_NE(outArray, nullptr) << inArray->GetName();
      EXPECT_EQ(outArray->GetDataType(), inArray->GetDataType());
      for (int k = 0; k < inArray->GetNumberOfComponents(); ++k)
      {
        EXPECT_EQ(outArray->GetComponent(t, k), inArray->GetComponent(origin, k));
      }
    }
  }

  // Field data passed; VertexClass added to the point data.
  for (int a = 0; a < input->GetFieldData()->GetNumberOfArrays(); ++a)
  {
    const char* name = input->GetFieldData()->GetAbstractArray(a)->GetName();
    EXPECT_NE(output->GetFieldData()->GetAbstractArray(name), nullptr) << name;
  }
  vtkDataArray* classes = output->GetPointData()->GetArray(Conversion::VertexClassName);
  ASSERT_NE(classes, nullptr);
  EXPECT_TRUE(vtkUnsignedCharArray::SafeDownCast(classes) != nullptr);
}

// Snapshot of a grid's points, connectivity and arrays, to check that a call
// left it as it was.
struct Snapshot
{
  std::vector<double> Coordinates;
  std::vector<vtkIdType> Connectivity;
  std::vector<std::string> ArrayNames;
  vtkMTimeType MTime = 0;

  explicit Snapshot(vtkUnstructuredGrid* grid)
  {
    for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
    {
      double p[3];
      grid->GetPoint(i, p);
      this->Coordinates.insert(this->Coordinates.end(), p, p + 3);
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      grid->GetCellPoints(c, ids);
      this->Connectivity.push_back(grid->GetCellType(c));
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        this->Connectivity.push_back(ids->GetId(k));
      }
    }
    for (vtkFieldData* fd :
      { static_cast<vtkFieldData*>(grid->GetPointData()),
        static_cast<vtkFieldData*>(grid->GetCellData()), grid->GetFieldData() })
    {
      this->ArrayNames.push_back("|");
      for (int a = 0; a < fd->GetNumberOfArrays(); ++a)
      {
        this->ArrayNames.push_back(fd->GetAbstractArray(a)->GetName());
      }
    }
    this->MTime = grid->GetMTime();
  }

  bool operator==(const Snapshot& o) const
  {
    // NaN coordinates compare by bits.
    if (this->Coordinates.size() != o.Coordinates.size())
    {
      return false;
    }
    for (std::size_t i = 0; i < this->Coordinates.size(); ++i)
    {
      const double a = this->Coordinates[i], b = o.Coordinates[i];
      if (!(a == b || (std::isnan(a) && std::isnan(b))))
      {
        return false;
      }
    }
    return this->Connectivity == o.Connectivity && this->ArrayNames == o.ArrayNames &&
      this->MTime == o.MTime;
  }
};

// Expects ToTetMesh to refuse `grid` with a message containing every word.
void ExpectRefused(vtkUnstructuredGrid* grid, const std::vector<std::string>& words)
{
  const Snapshot before(grid);
  femorph::TetMesh mesh;
  const femorph::Status status = Conversion::ToTetMesh(grid, "FEMorph Test", {}, mesh);
  EXPECT_FALSE(status.ok);
  for (const auto& word : words)
  {
    EXPECT_NE(status.message.find(word), std::string::npos)
      << "'" << word << "' not in: " << status.message;
  }
  EXPECT_EQ(mesh.live_tets(), 0u);
  EXPECT_TRUE(Snapshot(grid) == before) << "the input was modified";
}


} // namespace

TEST(MeshConversion, RoundTripHandBuiltGrid)
{
  auto input = MakeTwoTets();
  AddArrays(input);
  const Snapshot before(input);
  femorph::CompactMesh compact;
  auto output = RoundTrip(input, &compact);
  ExpectSameMesh(input, output, compact);
  EXPECT_TRUE(Snapshot(input) == before) << "the input was modified";
  // No region anywhere and no FaceRegion in the input: none in the output.
  EXPECT_EQ(output->GetCellData()->GetArray(Conversion::FaceRegionName), nullptr);
  // Every vertex of two tets is on the boundary.
  vtkDataArray* classes = output->GetPointData()->GetArray(Conversion::VertexClassName);
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    EXPECT_NE(classes->GetComponent(i, 0), 0) << "vertex " << i;
  }
}

TEST(MeshConversion, RoundTripFloatPoints)
{
  auto input = MakeTwoTets();
  vtkNew<vtkPoints> floats;
  floats->SetDataTypeToFloat();
  floats->DeepCopy(input->GetPoints());
  input->SetPoints(floats);
  femorph::CompactMesh compact;
  auto output = RoundTrip(input, &compact);
  ExpectSameMesh(input, output, compact);
  EXPECT_EQ(output->GetPoints()->GetDataType(), VTK_DOUBLE);
}

TEST(MeshConversion, RoundTripDataPart)
{
  auto input = femorph_test::ReadPart("boss_block.vtu");
  if (!input)
  {
    GTEST_SKIP() << "Data/boss_block.vtu not found";
  }
  ASSERT_GT(input->GetNumberOfCells(), 1000);
  femorph::CompactMesh compact;
  auto output = RoundTrip(input, &compact);
  ExpectSameMesh(input, output, compact);

  // Inner vertices are exactly the nodes Gmsh put inside the volume.
  vtkDataArray* dim = input->GetPointData()->GetArray("CADEntityDim");
  ASSERT_NE(dim, nullptr);
  vtkDataArray* classes = output->GetPointData()->GetArray(Conversion::VertexClassName);
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    const bool inner = classes->GetComponent(compact.vertex_map[i], 0) == 0;
    EXPECT_EQ(inner, dim->GetComponent(i, 0) == 3) << "point " << i;
  }
}

TEST(MeshConversion, FaceRegionPassesThrough)
{
  auto input = femorph_test::ReadPart("boss_block.vtu");
  if (!input)
  {
    GTEST_SKIP() << "Data/boss_block.vtu not found";
  }
  // The CAD face tags have FaceRegion's layout (Data/README.md).
  vtkNew<vtkIntArray> regions;
  regions->DeepCopy(input->GetCellData()->GetArray("CADFace"));
  regions->SetName(Conversion::FaceRegionName);
  input->GetCellData()->AddArray(regions);

  femorph::CompactMesh compact;
  auto output = RoundTrip(input, &compact);
  vtkDataArray* out = output->GetCellData()->GetArray(Conversion::FaceRegionName);
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(out->GetNumberOfComponents(), 4);
  vtkIdType boundaryFaces = 0;
  for (vtkIdType t = 0; t < output->GetNumberOfCells(); ++t)
  {
    const vtkIdType origin = compact.tet_origin[t];
    vtkNew<vtkIdList> in, o;
    input->GetCellPoints(origin, in);
    output->GetCellPoints(t, o);
    for (int f = 0; f < 4; ++f)
    {
      // Face f is opposite local vertex f: find the input's local index of
      // the same vertex, since the core may rotate a tet's vertices.
      int inLocal = -1;
      for (int k = 0; k < 4; ++k)
      {
        if (compact.vertex_map[in->GetId(k)] == o->GetId(f))
        {
          inLocal = k;
        }
      }
      ASSERT_GE(inLocal, 0);
      EXPECT_EQ(out->GetComponent(t, f), regions->GetComponent(origin, inLocal));
      boundaryFaces += out->GetComponent(t, f) >= 0;
    }
  }
  EXPECT_GT(boundaryFaces, 0);
}

TEST(MeshConversion, SplitEdgeInterpolatesAndInherits)
{
  auto input = MakeTwoTets();
  AddArrays(input);
  femorph::TetMesh mesh;
  ASSERT_TRUE(Conversion::ToTetMesh(input, "Test", {}, mesh).ok);

  // Edge (1, 2) lies on the shared face: both tets split, four children.
  femorph::index_t v = -1;
  ASSERT_EQ(mesh.split_edge(1, 2, nullptr, &v), femorph::OpStatus::Ok);
  const femorph::CompactMesh compact = mesh.compact();
  vtkNew<vtkUnstructuredGrid> output;
  Conversion::FromCompactMesh(compact, input, output);
  ASSERT_EQ(output->GetNumberOfPoints(), 6);
  ASSERT_EQ(output->GetNumberOfCells(), 4);

  const vtkIdType m = compact.vertex_map[v];
  const vtkIdType a = compact.vertex_map[1];
  const vtkIdType b = compact.vertex_map[2];
  vtkPointData* pd = output->GetPointData();
  vtkDataArray* temperature = pd->GetArray("Temperature");
  ASSERT_NE(temperature, nullptr);
  EXPECT_DOUBLE_EQ(temperature->GetComponent(m, 0),
    0.5 * (temperature->GetComponent(a, 0) + temperature->GetComponent(b, 0)));
  // Temperature is linear in space: the midpoint's value is also exact.
  double p[3];
  output->GetPoint(m, p);
  EXPECT_DOUBLE_EQ(temperature->GetComponent(m, 0), p[0] + 2 * p[1] + 3 * p[2]);
  // Labels 10 and 20: the integer average.
  EXPECT_EQ(pd->GetArray("Label")->GetComponent(m, 0), 15);

  // Every child carries its parent's cell data; each parent has two children.
  vtkDataArray* material = output->GetCellData()->GetArray("Material");
  vtkDataArray* stress = output->GetCellData()->GetArray("Stress");
  ASSERT_NE(material, nullptr);
  ASSERT_NE(stress, nullptr);
  int children[2] = { 0, 0 };
  for (vtkIdType t = 0; t < 4; ++t)
  {
    const vtkIdType parent = compact.tet_origin[t];
    ASSERT_TRUE(parent == 0 || parent == 1);
    ++children[parent];
    EXPECT_EQ(material->GetComponent(t, 0), 7 + parent);
    EXPECT_EQ(stress->GetComponent(t, 1), 2.0 * parent);
  }
  EXPECT_EQ(children[0], 2);
  EXPECT_EQ(children[1], 2);
}

TEST(MeshConversion, RefusesOtherCellTypes)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                         { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 }, { 0.5, 0.5, 2 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } }, { VTK_TETRA, { 4, 5, 6, 8 } },
      { VTK_TRIANGLE, { 0, 1, 2 } }, { VTK_TRIANGLE, { 0, 2, 3 } } });
  ExpectRefused(grid.Get(),
    { "FEMorph Test accepts tetrahedra only", "2 VTK_TRIANGLE and 1 VTK_HEXAHEDRON cells" });
}

TEST(MeshConversion, RefusesNonFiniteCoordinates)
{
  auto grid = MakeTwoTets();
  grid->GetPoints()->SetPoint(4, 1, std::numeric_limits<double>::quiet_NaN(), 1);
  ExpectRefused(grid.Get(), { "FEMorph Test", "1 point has NaN or infinite coordinates" });
  grid->GetPoints()->SetPoint(0, std::numeric_limits<double>::infinity(), 0, 0);
  ExpectRefused(grid.Get(), { "2 points have NaN or infinite coordinates" });
}

TEST(MeshConversion, RefusesMixedOrientation)
{
  // The second tet of MakeTwoTets with two vertices swapped: negative, and
  // inconsistent with its neighbour.
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 2, 3 } } });
  ExpectRefused(grid.Get(), { "FEMorph Test", "not valid", "orientation" });
}

TEST(MeshConversion, RefusesEmptyInput)
{
  vtkNew<vtkUnstructuredGrid> empty;
  ExpectRefused(empty.Get(), { "FEMorph Test", "no cells" });
  femorph::TetMesh mesh;
  EXPECT_FALSE(Conversion::ToTetMesh(nullptr, "FEMorph Test", {}, mesh).ok);
}

TEST(MeshConversion, WarnsAboutUnusedPoints)
{
  auto grid = MakeTwoTets();
  grid->GetPoints()->InsertNextPoint(5, 5, 5);
  AddArrays(grid);
  femorph::TetMesh mesh;
  femorph::BuildReport report;
  std::vector<std::string> warnings;
  ASSERT_TRUE(Conversion::ToTetMesh(grid, "FEMorph Test", {}, mesh, &report, &warnings).ok);
  EXPECT_EQ(report.unused_points, 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 point is not used"), std::string::npos) << warnings[0];
  vtkNew<vtkUnstructuredGrid> output;
  Conversion::FromCompactMesh(mesh.compact(), grid, output);
  EXPECT_EQ(output->GetNumberOfPoints(), 5);
  EXPECT_EQ(output->GetPointData()->GetArray("Label")->GetRange()[1], 40);
}

// ToTetMesh reads an int FaceRegion in place and any other numeric type
// value by value: both give the same regions.
TEST(MeshConversion, FaceRegionOfAnyNumericTypeGivesTheSameRegions)
{
  auto input = femorph_test::ReadPart("boss_block.vtu");
  if (!input)
  {
    GTEST_SKIP() << "Data/boss_block.vtu not found";
  }
  femorph::TetMesh meshes[2];
  for (int k = 0; k < 2; ++k)
  {
    vtkSmartPointer<vtkDataArray> regions;
    if (k == 0)
    {
      regions = vtkSmartPointer<vtkIntArray>::New();
    }
    else
    {
      regions = vtkSmartPointer<vtkDoubleArray>::New();
    }
    regions->DeepCopy(input->GetCellData()->GetArray("CADFace"));
    regions->SetName(Conversion::FaceRegionName);
    input->GetCellData()->AddArray(regions);
    ASSERT_TRUE(Conversion::ToTetMesh(input, "FEMorph Test", {}, meshes[k]).ok);
  }
  ASSERT_EQ(meshes[0].tet_slots(), meshes[1].tet_slots());
  std::size_t withRegion = 0;
  for (femorph::index_t t = 0; t < meshes[0].tet_slots(); ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      EXPECT_EQ(meshes[0].face_region(t, f), meshes[1].face_region(t, f));
      withRegion += meshes[0].face_region(t, f) >= 0;
    }
  }
  EXPECT_GT(withRegion, 1000u);
}

TEST(MeshConversion, WarnsAboutMalformedFaceRegion)
{
  auto grid = MakeTwoTets();
  vtkNew<vtkIntArray> regions;
  regions->SetName(Conversion::FaceRegionName);
  regions->InsertNextValue(1);
  regions->InsertNextValue(2);
  grid->GetCellData()->AddArray(regions);
  femorph::TetMesh mesh;
  std::vector<std::string> warnings;
  ASSERT_TRUE(Conversion::ToTetMesh(grid, "FEMorph Test", {}, mesh, nullptr, &warnings).ok);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 components instead of 4"), std::string::npos) << warnings[0];
}

TEST(MeshConversion, CellTypeNames)
{
  EXPECT_EQ(Conversion::CellTypeName(VTK_TETRA), "VTK_TETRA");
  EXPECT_EQ(Conversion::CellTypeName(VTK_POLYHEDRON), "VTK_POLYHEDRON");
  EXPECT_EQ(Conversion::CellTypeName(VTK_QUADRATIC_TETRA), "VTK_QUADRATIC_TETRA");
  EXPECT_EQ(Conversion::CellTypeName(200), "cell type 200");
  std::array<vtkIdType, 256> counts{};
  counts[VTK_HEXAHEDRON] = 120;
  counts[VTK_WEDGE] = 4;
  EXPECT_EQ(Conversion::DescribeCellCounts(counts), "120 VTK_HEXAHEDRON and 4 VTK_WEDGE cells");
  counts[VTK_PYRAMID] = 1;
  EXPECT_EQ(Conversion::DescribeCellCounts(counts),
    "120 VTK_HEXAHEDRON, 4 VTK_WEDGE and 1 VTK_PYRAMID cells");
  std::array<vtkIdType, 256> one{};
  one[VTK_VOXEL] = 1;
  EXPECT_EQ(Conversion::DescribeCellCounts(one), "1 VTK_VOXEL cell");
}
