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
using femorph_test::Snapshot;
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
vtkSmartPointer<vtkUnstructuredGrid> RoundTrip(vtkUnstructuredGrid* input,
  femorph::CompactMesh* compactOut = nullptr, const femorph::BuildOptions& options = {})
{
  femorph::TetMesh mesh;
  std::vector<std::string> warnings;
  const femorph::Status status =
    Conversion::ToTetMesh(input, options, mesh, nullptr, &warnings);
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


// Expects ToTetMesh to refuse `grid` with a message containing every word.
void ExpectRefused(vtkUnstructuredGrid* grid, const std::vector<std::string>& words)
{
  const Snapshot before(grid);
  femorph::TetMesh mesh;
  const femorph::Status status = Conversion::ToTetMesh(grid, {}, mesh);
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
  // The CAD face tags have FaceRegion's layout (Data/README.md); the caller
  // hands them to the conversion.
  vtkNew<vtkIntArray> regions;
  regions->DeepCopy(input->GetCellData()->GetArray("CADFace"));
  regions->SetName(Conversion::FaceRegionName);
  input->GetCellData()->AddArray(regions);
  femorph::BuildOptions options;
  options.face_regions.resize(static_cast<std::size_t>(input->GetNumberOfCells()));
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    for (int f = 0; f < 4; ++f)
    {
      options.face_regions[c][f] = regions->GetValue(4 * c + f);
    }
  }

  femorph::CompactMesh compact;
  auto output = RoundTrip(input, &compact, options);
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
  ASSERT_TRUE(Conversion::ToTetMesh(input, {}, mesh).ok);

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
    { "reads tetrahedra only", "2 VTK_TRIANGLE and 1 VTK_HEXAHEDRON cells" });
}

TEST(MeshConversion, RefusesNonFiniteCoordinates)
{
  auto grid = MakeTwoTets();
  grid->GetPoints()->SetPoint(4, 1, std::numeric_limits<double>::quiet_NaN(), 1);
  ExpectRefused(grid.Get(), { "1 point of the input has NaN or infinite coordinates" });
  grid->GetPoints()->SetPoint(0, std::numeric_limits<double>::infinity(), 0, 0);
  ExpectRefused(grid.Get(), { "2 points of the input have NaN or infinite coordinates" });
}

TEST(MeshConversion, RefusesMixedOrientation)
{
  // The second tet of MakeTwoTets with two vertices swapped: negative, and
  // inconsistent with its neighbour.
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 2, 3 } } });
  ExpectRefused(grid.Get(), { "not valid", "orientation" });
}

TEST(MeshConversion, RefusesEmptyInput)
{
  vtkNew<vtkUnstructuredGrid> empty;
  ExpectRefused(empty.Get(), { "no cells" });
  femorph::TetMesh mesh;
  EXPECT_FALSE(Conversion::ToTetMesh(nullptr, {}, mesh).ok);
}

TEST(MeshConversion, WarnsAboutUnusedPoints)
{
  auto grid = MakeTwoTets();
  grid->GetPoints()->InsertNextPoint(5, 5, 5);
  AddArrays(grid);
  femorph::TetMesh mesh;
  femorph::BuildReport report;
  std::vector<std::string> warnings;
  ASSERT_TRUE(Conversion::ToTetMesh(grid, {}, mesh, &report, &warnings).ok);
  EXPECT_EQ(report.unused_points, 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 point is not used"), std::string::npos) << warnings[0];
  vtkNew<vtkUnstructuredGrid> output;
  Conversion::FromCompactMesh(mesh.compact(), grid, output);
  EXPECT_EQ(output->GetNumberOfPoints(), 5);
  EXPECT_EQ(output->GetPointData()->GetArray("Label")->GetRange()[1], 40);
}

// The face regions come from BuildOptions only (the caller reads and checks
// them, vtkFEMorphSegmentationArrays::ReadFromMesh): a FaceRegion array on
// the grid, even one naming no region, is not read.
TEST(MeshConversion, FaceRegionsComeFromTheOptionsOnly)
{
  auto grid = MakeTwoTets();
  vtkNew<vtkIntArray> garbage;
  garbage->SetName(Conversion::FaceRegionName);
  garbage->SetNumberOfComponents(4);
  garbage->SetNumberOfTuples(2);
  garbage->Fill(VTK_INT_MAX);
  grid->GetCellData()->AddArray(garbage);
  femorph::TetMesh mesh;
  ASSERT_TRUE(Conversion::ToTetMesh(grid, {}, mesh).ok);
  for (femorph::index_t t = 0; t < 2; ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      EXPECT_EQ(mesh.face_region(t, f), -1);
    }
  }

  femorph::BuildOptions options;
  options.face_regions = { { 0, 1, 1, 1 }, { 0, 2, 1, 1 } };
  ASSERT_TRUE(Conversion::ToTetMesh(grid, options, mesh).ok);
  EXPECT_EQ(mesh.face_region(0, 0), -1); // the shared face (1, 2, 3) is interior
  EXPECT_EQ(mesh.face_region(0, 1), 1);
  EXPECT_EQ(mesh.face_region(1, 1), 2);
}

// One set of input checks for every filter, in a fixed order.
TEST(MeshConversion, CheckGridNamesEachProblem)
{
  using CellSet = Conversion::CellSet;
  auto good = MakeTwoTets();
  EXPECT_EQ(Conversion::CheckGrid(good, CellSet::Tetrahedra), "");

  auto badId = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 7 } } });
  EXPECT_NE(Conversion::CheckGrid(badId, CellSet::Any, "the Reference input")
              .find("cell 0 of the Reference input refers to point 7, but there are 4 points"),
    std::string::npos);

  auto shortTet = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2 } } });
  EXPECT_NE(Conversion::CheckGrid(shortTet, CellSet::Tetrahedra)
              .find("cell 0 of the input is a VTK_TETRA with 3 points instead of 4"),
    std::string::npos);

  auto mixed = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TRIANGLE, { 0, 1, 2 } } });
  EXPECT_EQ(Conversion::CheckGrid(mixed, CellSet::Any), "");
  EXPECT_NE(Conversion::CheckGrid(mixed, CellSet::Linear3D).find("1 VTK_TRIANGLE cell"),
    std::string::npos);

  auto unknownType = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { 99, { 0, 1, 2, 3 } } });
  EXPECT_NE(Conversion::CheckGrid(unknownType, CellSet::Any)
              .find("cell 1 of the input has the type 99, which is no VTK cell type"),
    std::string::npos);
  auto fourPointTriangle = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TRIANGLE, { 0, 1, 2, 3 } } });
  EXPECT_NE(Conversion::CheckGrid(fourPointTriangle, CellSet::Any)
              .find("cell 1 of the input is a VTK_TRIANGLE with 4 points instead of 3"),
    std::string::npos);

  vtkNew<vtkUnstructuredGrid> noPoints;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  noPoints->InsertNextCell(VTK_TETRA, 4, ids);
  EXPECT_NE(Conversion::CheckGrid(noPoints, CellSet::Tetrahedra).find("1 cell but no points"),
    std::string::npos);
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
