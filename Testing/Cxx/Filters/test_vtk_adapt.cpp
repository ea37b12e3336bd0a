// FEMorph Adapt (vtkFEMorphAdapt, thesis chapter 3) on a block of cubes with
// a small object inside: the time steps, the cache (a step asked again is
// not recomputed), a valid conforming output whose outer boundary does not
// change, the object moved rigidly, the carried arrays, the Motion table,
// and the bad-input errors; every check computed here, not by the core.
#include "vtkFEMorphAdapt.h"
#include "vtkFEMorphMeshConversion.h"

#include "filters_test_utils.h"

#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using femorph_test::MessageRecorder;
using femorph_test::Snapshot;
using Vec3 = Eigen::Vector3d;

constexpr int NX = 6, NY = 6, NZ = 8;
// The object: cubes i, j in {2, 3}, k = 3, so x, y in [2, 4], z in [3, 4].
const Vec3 BlockCentre(3, 3, 3.5);
constexpr int ObjectTets = 4 * 12;

/// NX x NY x NZ unit cubes, each split into 12 tetrahedra around its centre
/// (each face into two triangles by the diagonal from its lowest point id, so
/// neighbours agree); cell arrays MaterialId (1 on the object's cubes) and
/// CellTag (the cell id), point arrays Temperature (x + 2y + 3z) and
/// NodeLabel (the point id, int).
vtkSmartPointer<vtkUnstructuredGrid> MakeAssembly()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const auto lattice = [](int i, int j, int k) {
    return static_cast<vtkIdType>((k * (NY + 1) + j) * (NX + 1) + i);
  };
  for (int k = 0; k <= NZ; ++k)
  {
    for (int j = 0; j <= NY; ++j)
    {
      for (int i = 0; i <= NX; ++i)
      {
        points->InsertNextPoint(i, j, k);
      }
    }
  }
  vtkNew<vtkIntArray> material;
  material->SetName("MaterialId");
  grid->AllocateExact(NX * NY * NZ * 12, 4);
  for (int k = 0; k < NZ; ++k)
  {
    for (int j = 0; j < NY; ++j)
    {
      for (int i = 0; i < NX; ++i)
      {
        const vtkIdType centre = points->InsertNextPoint(i + 0.5, j + 0.5, k + 0.5);
        const bool object = (i == 2 || i == 3) && (j == 2 || j == 3) && k == 3;
        // The six faces, corners in cyclic order.
        const int faces[6][4][3] = { { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 1, 1 }, { 0, 0, 1 } },
          { { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 1, 0, 1 } },
          { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 1 }, { 0, 0, 1 } },
          { { 0, 1, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 0, 1, 1 } },
          { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } },
          { { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } } };
        for (const auto& face : faces)
        {
          vtkIdType q[4];
          for (int c = 0; c < 4; ++c)
          {
            q[c] = lattice(i + face[c][0], j + face[c][1], k + face[c][2]);
          }
          const int m = static_cast<int>(std::min_element(q, q + 4) - q);
          const vtkIdType tris[2][3] = { { q[m], q[(m + 1) % 4], q[(m + 2) % 4] },
            { q[m], q[(m + 2) % 4], q[(m + 3) % 4] } };
          for (const auto& tri : tris)
          {
            vtkIdType tet[4] = { tri[0], tri[1], tri[2], centre };
            double p[4][3];
            for (int c = 0; c < 4; ++c)
            {
              points->GetPoint(tet[c], p[c]);
            }
            const Vec3 a(p[0]), b(p[1]), c(p[2]), d(p[3]);
            if ((b - a).dot((c - a).cross(d - a)) < 0)
            {
              std::swap(tet[1], tet[2]);
            }
            grid->InsertNextCell(VTK_TETRA, 4, tet);
            material->InsertNextValue(object ? 1 : 0);
          }
        }
      }
    }
  }
  grid->SetPoints(points);
  grid->GetCellData()->AddArray(material);
  vtkNew<vtkIntArray> tag;
  tag->SetName("CellTag");
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    tag->InsertNextValue(static_cast<int>(c));
  }
  grid->GetCellData()->AddArray(tag);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  vtkNew<vtkIntArray> label;
  label->SetName("NodeLabel");
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    temperature->InsertNextValue(x[0] + 2 * x[1] + 3 * x[2]);
    label->InsertNextValue(static_cast<int>(p));
  }
  grid->GetPointData()->AddArray(temperature);
  grid->GetPointData()->AddArray(label);
  return grid;
}

/// The pose of step n of the test's motion: 0.1 along z and 2 degrees about
/// x through the block's centre per step.
Eigen::Isometry3d Pose(int n)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(BlockCentre + Vec3(0, 0, 0.1 * n));
  pose.rotate(Eigen::AngleAxisd(n * 2.0 * M_PI / 180.0, Vec3::UnitX()));
  pose.translate(-BlockCentre);
  return pose;
}

void SetMotion(vtkFEMorphAdapt* filter, int steps)
{
  filter->SetTranslationPerStep(0, 0, 0.1);
  filter->SetRotationAxis(1, 0, 0);
  filter->SetRotationCenter(BlockCentre.data());
  filter->SetRotationAnglePerStep(2);
  filter->SetNumberOfSteps(steps);
}

Vec3 PointOf(vtkUnstructuredGrid* grid, vtkIdType id)
{
  Vec3 x;
  grid->GetPoint(id, x.data());
  return x;
}

/// A triangle by its corners' coordinates, sorted (ids differ between the
/// input and the output).
using FaceKey = std::array<double, 9>;
FaceKey Key(vtkUnstructuredGrid* grid, const std::array<vtkIdType, 3>& ids)
{
  std::array<std::array<double, 3>, 3> p;
  for (int c = 0; c < 3; ++c)
  {
    grid->GetPoint(ids[c], p[c].data());
  }
  std::sort(p.begin(), p.end());
  FaceKey key;
  for (int c = 0; c < 9; ++c)
  {
    key[c] = p[c / 3][c % 3];
  }
  return key;
}

struct MeshCheck
{
  std::size_t NonPositive = 0;     ///< tets of volume <= 0
  std::size_t OverShared = 0;      ///< faces in more than 2 tets
  std::set<FaceKey> Boundary;      ///< faces in exactly one tet
};

/// Volumes and face sharing of a tet grid, computed here.
MeshCheck CheckMesh(vtkUnstructuredGrid* grid)
{
  MeshCheck check;
  std::map<std::array<vtkIdType, 3>, int> faces;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(grid->GetCellType(c), VTK_TETRA);
    vtkIdType n = 0;
    const vtkIdType* p = nullptr;
    grid->GetCellPoints(c, n, p);
    EXPECT_EQ(n, 4);
    if (n != 4)
    {
      continue;
    }
    const Vec3 a = PointOf(grid, p[0]), b = PointOf(grid, p[1]), cc = PointOf(grid, p[2]),
               d = PointOf(grid, p[3]);
    check.NonPositive += !((b - a).dot((cc - a).cross(d - a)) > 0);
    for (int f = 0; f < 4; ++f)
    {
      std::array<vtkIdType, 3> face = { p[(f + 1) % 4], p[(f + 2) % 4], p[(f + 3) % 4] };
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  }
  for (const auto& entry : faces)
  {
    check.OverShared += entry.second > 2;
    if (entry.second == 1)
    {
      check.Boundary.insert(Key(grid, entry.first));
    }
  }
  return check;
}

/// Runs the filter at `time`; returns the executive's result.
int RunAt(vtkFEMorphAdapt* filter, double time)
{
  return filter->UpdateTimeStep(time);
}

class AdaptTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    this->Input = MakeAssembly();
    this->Filter->SetInputData(this->Input);
    this->Messages->Observe(this->Filter);
    // The executive's "returned failure" stays off the output.
    this->PipelineMessages->Observe(this->Filter->GetExecutive());
  }

  void ExpectEmptyOutputs()
  {
    EXPECT_EQ(this->Filter->GetMeshOutput()->GetNumberOfCells(), 0);
    EXPECT_EQ(this->Filter->GetMeshOutput()->GetNumberOfPoints(), 0);
    EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 0);
  }

  /// One error containing `words`, empty outputs, the input as it was.
  void ExpectError(double time, const std::string& words)
  {
    const Snapshot before(this->Input);
    this->Messages->Errors.clear();
    RunAt(this->Filter, time);
    ASSERT_EQ(this->Messages->Errors.size(), 1u) << this->Messages->AllErrors();
    EXPECT_NE(this->Messages->Errors[0].find("FEMorph Adapt: "), std::string::npos);
    EXPECT_NE(this->Messages->Errors[0].find(words), std::string::npos) << this->Messages->Errors[0];
    this->ExpectEmptyOutputs();
    EXPECT_TRUE(Snapshot(this->Input) == before) << "the input was modified";
  }

  vtkSmartPointer<vtkUnstructuredGrid> Input;
  vtkNew<vtkFEMorphAdapt> Filter;
  vtkNew<MessageRecorder> Messages;
  vtkNew<MessageRecorder> PipelineMessages;
};

} // namespace

TEST_F(AdaptTest, TimeStepsAreTheMotionSteps)
{
  SetMotion(this->Filter, 3);
  this->Filter->UpdateInformation();
  vtkInformation* info = this->Filter->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  const int n = info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  ASSERT_EQ(n, 4);
  const double* times = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  for (int k = 0; k < n; ++k)
  {
    EXPECT_EQ(times[k], k);
  }
  const double* range = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  EXPECT_EQ(range[0], 0);
  EXPECT_EQ(range[1], 3);

  // Step 0 is the input.
  ASSERT_EQ(RunAt(this->Filter, 0), 1);
  EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
  vtkUnstructuredGrid* out = this->Filter->GetMeshOutput();
  EXPECT_EQ(out->GetNumberOfPoints(), this->Input->GetNumberOfPoints());
  EXPECT_EQ(out->GetNumberOfCells(), this->Input->GetNumberOfCells());
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    ASSERT_EQ(PointOf(out, p), PointOf(this->Input, p));
  }
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 0);
}

TEST_F(AdaptTest, ThreeStepsValidRigidAndCached)
{
  SetMotion(this->Filter, 3);
  const Snapshot before(this->Input);
  const MeshCheck input = CheckMesh(this->Input);
  ASSERT_EQ(input.NonPositive, 0u);
  ASSERT_EQ(input.OverShared, 0u);

  ASSERT_EQ(RunAt(this->Filter, 3), 1);
  ASSERT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  vtkUnstructuredGrid* out = this->Filter->GetMeshOutput();
  ASSERT_GT(out->GetNumberOfCells(), 0);
  EXPECT_EQ(out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 3);
  // The step's summary in field data.
  auto* step = vtkIdTypeArray::SafeDownCast(out->GetFieldData()->GetArray("AdaptStep"));
  ASSERT_NE(step, nullptr);
  EXPECT_EQ(step->GetValue(0), 3);
  vtkDataArray* stretch = out->GetFieldData()->GetArray("AdaptStretch");
  ASSERT_NE(stretch, nullptr);
  ASSERT_EQ(stretch->GetNumberOfComponents(), 2);
  EXPECT_GT(stretch->GetComponent(0, 0), 0.0);
  EXPECT_GE(stretch->GetComponent(0, 1), stretch->GetComponent(0, 0));

  // Valid and conforming; the outer boundary is the input's.
  const MeshCheck check = CheckMesh(out);
  EXPECT_EQ(check.NonPositive, 0u);
  EXPECT_EQ(check.OverShared, 0u);
  EXPECT_TRUE(check.Boundary == input.Boundary) << check.Boundary.size() << " boundary faces, input "
                                                << input.Boundary.size();

  // The object moved rigidly: its points mapped back by the inverse pose
  // are the input's object points, and it kept its tets.
  auto* material = vtkIntArray::SafeDownCast(out->GetCellData()->GetArray("MaterialId"));
  ASSERT_NE(material, nullptr) << "MaterialId is not an int cell array";
  std::set<vtkIdType> objectPoints;
  vtkIdType objectTets = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    const int m = material->GetValue(c);
    EXPECT_TRUE(m == 0 || m == 1) << m;
    if (m == 1)
    {
      ++objectTets;
      vtkIdType n = 0;
      const vtkIdType* p = nullptr;
      out->GetCellPoints(c, n, p);
      objectPoints.insert(p, p + n);
    }
  }
  EXPECT_EQ(objectTets, ObjectTets);
  std::vector<Vec3> rest;
  std::set<vtkIdType> inputObject;
  for (vtkIdType c = 0; c < this->Input->GetNumberOfCells(); ++c)
  {
    if (this->Input->GetCellData()->GetArray("MaterialId")->GetComponent(c, 0) == 1)
    {
      vtkIdType n = 0;
      const vtkIdType* p = nullptr;
      this->Input->GetCellPoints(c, n, p);
      inputObject.insert(p, p + n);
    }
  }
  for (const vtkIdType p : inputObject)
  {
    rest.push_back(PointOf(this->Input, p));
  }
  EXPECT_EQ(objectPoints.size(), inputObject.size());
  const Eigen::Isometry3d back = Pose(3).inverse();
  for (const vtkIdType p : objectPoints)
  {
    const Vec3 x = back * PointOf(out, p);
    double nearest = 1e300;
    for (const Vec3& r : rest)
    {
      nearest = std::min(nearest, (x - r).norm());
    }
    EXPECT_LT(nearest, 1e-9) << "object point " << p << " is not the input's moved rigidly";
  }

  // Carried arrays: cell data from the input cell (an object tet keeps an
  // object tag), point data interpolated (an id array takes input ids).
  vtkDataArray* tag = out->GetCellData()->GetArray("CellTag");
  ASSERT_NE(tag, nullptr);
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    const vtkIdType source = static_cast<vtkIdType>(tag->GetComponent(c, 0));
    ASSERT_TRUE(source >= 0 && source < this->Input->GetNumberOfCells());
    EXPECT_EQ(
      this->Input->GetCellData()->GetArray("MaterialId")->GetComponent(source, 0), material->GetValue(c));
  }
  vtkDataArray* label = out->GetPointData()->GetArray("NodeLabel");
  vtkDataArray* temperature = out->GetPointData()->GetArray("Temperature");
  ASSERT_NE(label, nullptr);
  ASSERT_NE(temperature, nullptr);
  EXPECT_TRUE(vtkIntArray::SafeDownCast(label) != nullptr);
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    const double id = label->GetComponent(p, 0);
    ASSERT_TRUE(id >= 0 && id < this->Input->GetNumberOfPoints()) << id;
    // A point where an input point was: its exact value.
    const Vec3 x = PointOf(out, p);
    if (x == PointOf(this->Input, static_cast<vtkIdType>(id)) && objectPoints.count(p) == 0)
    {
      EXPECT_EQ(temperature->GetComponent(p, 0), x.x() + 2 * x.y() + 3 * x.z());
    }
  }

  // One table row per step 0..3.
  vtkTable* table = this->Filter->GetStepsOutput();
  ASSERT_EQ(table->GetNumberOfRows(), 4);
  for (const char* column : { "Step", "Vertices", "Tetrahedra", "MinStretch", "MeanStretch",
         "DeformedRegionTets", "ContactFaces", "Seconds" })
  {
    ASSERT_NE(table->GetColumnByName(column), nullptr) << column;
  }
  EXPECT_EQ(table->GetValueByName(3, "Tetrahedra").ToLongLong(), out->GetNumberOfCells());
  EXPECT_EQ(table->GetValueByName(3, "Vertices").ToLongLong(), out->GetNumberOfPoints());
  EXPECT_GT(table->GetValueByName(3, "DeformedRegionTets").ToLongLong(), 0);
  EXPECT_EQ(table->GetValueByName(0, "Tetrahedra").ToLongLong(), this->Input->GetNumberOfCells());

  // Back to step 1, then 3 and 2: from the cache, nothing recomputed.
  ASSERT_EQ(RunAt(this->Filter, 1), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 2);
  const MeshCheck one = CheckMesh(this->Filter->GetMeshOutput());
  EXPECT_EQ(one.NonPositive, 0u);
  EXPECT_TRUE(one.Boundary == input.Boundary);
  ASSERT_EQ(RunAt(this->Filter, 3), 1);
  ASSERT_EQ(RunAt(this->Filter, 2), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();

  // A time between steps is the nearest step.
  ASSERT_EQ(RunAt(this->Filter, 1.4), 1);
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 2);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  EXPECT_TRUE(Snapshot(this->Input) == before) << "the input was modified";

  // A property change clears the cache.
  this->Filter->SetDistanceThreshold(4);
  ASSERT_EQ(RunAt(this->Filter, 1), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 4);
}

// Without room for copies only step 0 is kept: an earlier step is computed
// again from there, and gives the same mesh.
TEST_F(AdaptTest, CacheMemoryLimitKeepsStepZero)
{
  SetMotion(this->Filter, 3);
  this->Filter->SetCacheMemoryLimit(0);
  ASSERT_EQ(RunAt(this->Filter, 2), 1);
  vtkNew<vtkUnstructuredGrid> first;
  first->DeepCopy(this->Filter->GetMeshOutput());
  ASSERT_EQ(RunAt(this->Filter, 3), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  EXPECT_EQ(this->Filter->GetNumberOfCachedSteps(), 1);
  ASSERT_EQ(RunAt(this->Filter, 2), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 5);
  EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
  vtkUnstructuredGrid* again = this->Filter->GetMeshOutput();
  ASSERT_EQ(again->GetNumberOfPoints(), first->GetNumberOfPoints());
  ASSERT_EQ(again->GetNumberOfCells(), first->GetNumberOfCells());
  for (vtkIdType p = 0; p < again->GetNumberOfPoints(); ++p)
  {
    ASSERT_EQ(PointOf(again, p), PointOf(first, p)) << "point " << p;
  }

  // With room, every step is kept.
  vtkNew<vtkFEMorphAdapt> roomy;
  roomy->SetInputData(this->Input);
  SetMotion(roomy, 3);
  ASSERT_EQ(RunAt(roomy, 3), 1);
  EXPECT_EQ(roomy->GetNumberOfCachedSteps(), 4);
}

namespace
{
/// Aborts the filter when its progress text reaches `Step`.
class AbortAt : public vtkCommand
{
public:
  static AbortAt* New() { return new AbortAt; }
  void Execute(vtkObject* caller, unsigned long, void*) override
  {
    auto* algorithm = vtkAlgorithm::SafeDownCast(caller);
    const char* text = algorithm ? algorithm->GetProgressText() : nullptr;
    if (text && this->Step == text)
    {
      algorithm->SetAbortExecute(1);
    }
  }
  std::string Step;
};
}

// Progress per step; an abort between steps leaves the outputs empty, keeps
// the steps done, and the next request goes on from them.
TEST_F(AdaptTest, AbortBetweenStepsKeepsTheStepsDone)
{
  SetMotion(this->Filter, 3);
  vtkNew<AbortAt> abort;
  abort->Step = "step 3 of 3";
  const unsigned long tag = this->Filter->AddObserver(vtkCommand::ProgressEvent, abort);
  RunAt(this->Filter, 3);
  EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
  this->ExpectEmptyOutputs();
  EXPECT_EQ(this->Filter->GetComputedSteps(), 2);
  this->Filter->RemoveObserver(tag);
  this->Filter->SetAbortExecute(0);
  ASSERT_EQ(RunAt(this->Filter, 3), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 3);
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 4);
  EXPECT_GT(this->Filter->GetMeshOutput()->GetNumberOfCells(), 0);
}

namespace
{
/// A Motion table of the test's poses for steps 1..rows; `scale` scales
/// row `scaledRow` (0-based), making it non-rigid.
vtkSmartPointer<vtkTable> MotionTable(int rows, int scaledRow = -1, double scale = 1)
{
  auto table = vtkSmartPointer<vtkTable>::New();
  for (int k = 0; k < 16; ++k)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(("m" + std::to_string(k / 4) + std::to_string(k % 4)).c_str());
    column->SetNumberOfValues(rows);
    table->AddColumn(column);
  }
  for (int r = 0; r < rows; ++r)
  {
    Eigen::Matrix4d m = Pose(r + 1).matrix();
    if (r == scaledRow)
    {
      m.topLeftCorner<3, 3>() *= scale;
    }
    for (int k = 0; k < 16; ++k)
    {
      vtkDoubleArray::SafeDownCast(table->GetColumn(k))->SetValue(r, m(k / 4, k % 4));
    }
  }
  return table;
}
}

// The table's poses, its rows capping the steps; a new NumberOfSteps keeps
// the steps computed (and the motion: every row is read).
TEST_F(AdaptTest, MotionTableGivesThePosesAndCapsTheSteps)
{
  this->Filter->SetNumberOfSteps(1);
  this->Filter->SetInputData(1, MotionTable(2));
  ASSERT_EQ(RunAt(this->Filter, 1), 1);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 1);
  this->Filter->SetNumberOfSteps(10);
  this->Filter->UpdateInformation();
  EXPECT_EQ(this->Filter->GetOutputInformation(0)->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 3);
  ASSERT_EQ(RunAt(this->Filter, 10), 1);
  ASSERT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), 3);
  EXPECT_EQ(this->Filter->GetComputedSteps(), 2);

  // The same mesh as with the motion properties.
  vtkNew<vtkFEMorphAdapt> byProperties;
  byProperties->SetInputData(this->Input);
  SetMotion(byProperties, 2);
  ASSERT_EQ(RunAt(byProperties, 2), 1);
  vtkUnstructuredGrid* a = this->Filter->GetMeshOutput();
  vtkUnstructuredGrid* b = byProperties->GetMeshOutput();
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    EXPECT_LT((PointOf(a, p) - PointOf(b, p)).norm(), 1e-9) << "point " << p;
  }
}

TEST_F(AdaptTest, NonRigidTableRowIsAnError)
{
  this->Filter->SetNumberOfSteps(3);
  this->Filter->SetInputData(1, MotionTable(3, 1, 2.0));
  this->ExpectError(3, "row 2 (step 2) of the Motion table is not a rigid motion");
  // A column missing.
  auto table = MotionTable(3);
  table->RemoveColumnByName("m21");
  this->Filter->SetInputData(1, table);
  this->ExpectError(3, "no column m21");
}

TEST_F(AdaptTest, MaterialArrayErrors)
{
  SetMotion(this->Filter, 2);
  this->Filter->SetMaterialArray("Nope");
  this->ExpectError(1, "MaterialArray is 'Nope', but the input has no cell array of that name");

  // Not an integer array.
  this->Filter->SetMaterialArray("Real");
  vtkNew<vtkFloatArray> real;
  real->SetName("Real");
  real->SetNumberOfValues(this->Input->GetNumberOfCells());
  real->Fill(0);
  this->Input->GetCellData()->AddArray(real);
  this->ExpectError(1, "ids need an integer array");

  // A negative id.
  this->Filter->SetMaterialArray("Signed");
  vtkNew<vtkIntArray> negative;
  negative->DeepCopy(this->Input->GetCellData()->GetArray("MaterialId"));
  negative->SetName("Signed");
  negative->SetValue(5, -1);
  this->Input->GetCellData()->AddArray(negative);
  this->ExpectError(1, "has the value -1 at cell 5");

  // No cell of the moving object.
  this->Filter->SetMaterialArray("MaterialId");
  this->Filter->SetMovingObject(7);
  this->ExpectError(1, "no cell has the MovingObject id 7 in 'MaterialId' (its ids: 0, 1)");
}

// An object pushed out of the domain: a step is refused, the error names it,
// and that time and later ones show the last good step.
TEST_F(AdaptTest, RefusedStepKeepsTheLastGoodOne)
{
  this->Filter->SetTranslationPerStep(0, 0, 1.5);
  this->Filter->SetNumberOfSteps(4);
  RunAt(this->Filter, 4);
  ASSERT_EQ(this->Messages->Errors.size(), 1u) << this->Messages->AllErrors();
  const std::string& error = this->Messages->Errors[0];
  const std::size_t at = error.find("step ");
  ASSERT_NE(at, std::string::npos) << error;
  const int refused = std::stoi(error.substr(at + 5));
  ASSERT_TRUE(refused >= 1 && refused <= 4) << error;
  EXPECT_NE(error.find("is the mesh of step " + std::to_string(refused - 1)), std::string::npos) << error;
  EXPECT_EQ(this->Filter->GetStepsOutput()->GetNumberOfRows(), refused);
  EXPECT_GT(this->Filter->GetMeshOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(CheckMesh(this->Filter->GetMeshOutput()).NonPositive, 0u);
  // An earlier time is fine.
  this->Messages->Errors.clear();
  ASSERT_EQ(RunAt(this->Filter, refused - 1), 1);
  EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
}

// Point data onto new points by the stencils: a weighted sum, but an id
// (integer) or a label (string) from the largest weight.
TEST(Adapt, InterpolatePointDataTakesIdsFromTheLargestWeight)
{
  auto input = femorph_test::MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }, {});
  vtkNew<vtkIntArray> id;
  id->SetName("Id");
  vtkNew<vtkDoubleArray> value;
  value->SetName("Value");
  vtkNew<vtkStringArray> label;
  label->SetName("Label");
  for (int p = 0; p < 3; ++p)
  {
    id->InsertNextValue(10 * (p + 1));
    value->InsertNextValue(p + 1);
    label->InsertNextValue(std::string(1, static_cast<char>('a' + p)));
  }
  input->GetPointData()->AddArray(id);
  input->GetPointData()->AddArray(value);
  input->GetPointData()->AddArray(label);
  std::vector<femorph::VertexStencil> stencils(3);
  stencils[0].ids = { { 2, -1, -1, -1 } };
  stencils[0].weights = { { 1, 0, 0, 0 } };
  stencils[1].ids = { { 0, 1, -1, -1 } };
  stencils[1].weights = { { 0.3, 0.7, 0, 0 } };
  stencils[2].ids = { { 0, 1, 2, -1 } };
  stencils[2].weights = { { 0.2, 0.3, 0.5, 0 } };
  auto output = femorph_test::MakeGrid({ { 0, 1, 0 }, { 0.7, 0, 0 }, { 0.3, 0.5, 0 } }, {});
  vtkFEMorphMeshConversion::InterpolatePointData(input, stencils, output);
  vtkPointData* pd = output->GetPointData();
  ASSERT_NE(vtkIntArray::SafeDownCast(pd->GetAbstractArray("Id")), nullptr);
  ASSERT_NE(vtkStringArray::SafeDownCast(pd->GetAbstractArray("Label")), nullptr);
  const int ids[3] = { 30, 20, 30 };
  const double values[3] = { 3, 1.7, 2.3 };
  const char* labels[3] = { "c", "b", "c" };
  for (vtkIdType p = 0; p < 3; ++p)
  {
    EXPECT_EQ(vtkIntArray::SafeDownCast(pd->GetAbstractArray("Id"))->GetValue(p), ids[p]) << p;
    EXPECT_NEAR(pd->GetArray("Value")->GetComponent(p, 0), values[p], 1e-12) << p;
    EXPECT_EQ(vtkStringArray::SafeDownCast(pd->GetAbstractArray("Label"))->GetValue(p), labels[p]) << p;
  }
}

TEST(Adapt, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy =
    femorph_test::FindFilterProxy(FEMORPH_PLUGIN_XML, "vtkFEMorphAdapt", "FEMorphAdapt", "FEMorph Adapt",
      root);
  ASSERT_NE(proxy, nullptr);
  vtkNew<vtkFEMorphAdapt> d;
  const std::map<std::string, std::vector<double>> expected = {
    { "SetMovingObject", { double(d->GetMovingObject()) } },
    { "SetTranslationPerStep",
      { d->GetTranslationPerStep()[0], d->GetTranslationPerStep()[1], d->GetTranslationPerStep()[2] } },
    { "SetRotationAxis", { d->GetRotationAxis()[0], d->GetRotationAxis()[1], d->GetRotationAxis()[2] } },
    { "SetRotationCenter",
      { d->GetRotationCenter()[0], d->GetRotationCenter()[1], d->GetRotationCenter()[2] } },
    { "SetRotationAnglePerStep", { d->GetRotationAnglePerStep() } },
    { "SetNumberOfSteps", { double(d->GetNumberOfSteps()) } },
    { "SetDistanceThreshold", { d->GetDistanceThreshold() } },
    { "SetGridCellSize", { d->GetGridCellSize() } },
    { "SetImprove", { double(d->GetImprove()) } },
    { "SetQualityFloor", { d->GetQualityFloor() } },
    { "SetCacheMemoryLimit", { double(d->GetCacheMemoryLimit()) } },
  };
  // Ranges of the clamped properties.
  const std::map<std::string, std::pair<double, double>> ranges = {
    { "SetMovingObject", { d->GetMovingObjectMinValue(), d->GetMovingObjectMaxValue() } },
    { "SetRotationAnglePerStep",
      { d->GetRotationAnglePerStepMinValue(), d->GetRotationAnglePerStepMaxValue() } },
    { "SetNumberOfSteps", { d->GetNumberOfStepsMinValue(), d->GetNumberOfStepsMaxValue() } },
    { "SetDistanceThreshold", { d->GetDistanceThresholdMinValue(), d->GetDistanceThresholdMaxValue() } },
    { "SetGridCellSize", { d->GetGridCellSizeMinValue(), d->GetGridCellSizeMaxValue() } },
    { "SetQualityFloor", { d->GetQualityFloorMinValue(), d->GetQualityFloorMaxValue() } },
    { "SetCacheMemoryLimit", { d->GetCacheMemoryLimitMinValue(), d->GetCacheMemoryLimitMaxValue() } },
  };
  std::set<std::string> seen;
  bool timesteps = false;
  for (int i = 0; i < proxy->GetNumberOfNestedElements(); ++i)
  {
    vtkXMLDataElement* e = proxy->GetNestedElement(i);
    const char* name = e->GetAttribute("name");
    if (name && std::string(name) == "TimestepValues")
    {
      timesteps = e->FindNestedElementWithName("TimeStepsInformationHelper") != nullptr;
    }
    const char* command = e->GetAttribute("command");
    if (!command || std::string(e->GetName()) == "InputProperty")
    {
      continue;
    }
    EXPECT_NE(e->FindNestedElementWithName("Documentation"), nullptr) << command;
    seen.insert(command);
    if (std::string(command) == "SetMaterialArray")
    {
      EXPECT_STREQ(e->GetAttribute("default_values"), d->GetMaterialArray());
      continue;
    }
    const auto it = expected.find(command);
    if (it == expected.end())
    {
      ADD_FAILURE() << "add a default check for " << command;
      continue;
    }
    std::istringstream values(e->GetAttribute("default_values") ? e->GetAttribute("default_values") : "");
    std::vector<double> xml;
    for (double v; values >> v;)
    {
      xml.push_back(v);
    }
    EXPECT_EQ(xml, it->second) << command;
    const auto range = ranges.find(command);
    vtkXMLDataElement* domain = e->FindNestedElementWithName("DoubleRangeDomain");
    domain = domain ? domain : e->FindNestedElementWithName("IntRangeDomain");
    if (range != ranges.end())
    {
      ASSERT_NE(domain, nullptr) << command;
      EXPECT_EQ(std::stod(domain->GetAttribute("min")), range->second.first) << command;
      EXPECT_EQ(std::stod(domain->GetAttribute("max")), range->second.second) << command;
    }
  }
  EXPECT_EQ(seen.size(), expected.size() + 1);
  EXPECT_TRUE(timesteps) << "no TimestepValues information property";
  // The ports: Motion an optional vtkTable on port 1, outputs Mesh and Steps.
  vtkXMLDataElement* motion = proxy->FindNestedElementWithNameAndAttribute("InputProperty", "name", "Motion");
  ASSERT_NE(motion, nullptr);
  EXPECT_STREQ(motion->GetAttribute("port_index"), "1");
  vtkXMLDataElement* types = motion->FindNestedElementWithName("DataTypeDomain");
  ASSERT_NE(types, nullptr);
  EXPECT_NE(types->FindNestedElementWithNameAndAttribute("DataType", "value", "vtkTable"), nullptr);
  vtkXMLDataElement* hints = motion->FindNestedElementWithName("Hints");
  EXPECT_TRUE(hints && hints->FindNestedElementWithName("Optional"));
  EXPECT_NE(proxy->FindNestedElementWithNameAndAttribute("OutputPort", "name", "Mesh"), nullptr);
  EXPECT_NE(proxy->FindNestedElementWithNameAndAttribute("OutputPort", "name", "Steps"), nullptr);
  // The help names the output's columns.
  vtkXMLDataElement* doc = proxy->FindNestedElementWithName("Documentation");
  ASSERT_NE(doc, nullptr);
  const std::string help = doc->GetCharacterData() ? doc->GetCharacterData() : "";
  for (const char* name : { "MaterialId", "Step", "Vertices", "Tetrahedra", "MinStretch", "MeanStretch",
         "DeformedRegionTets", "ContactFaces", "Seconds" })
  {
    EXPECT_NE(help.find(name), std::string::npos) << name;
  }
}

// The assembly mode (thesis 3.7.4): Data/adapt/assembly_crank.vtu has no
// space cell (no material 0), its crank and bearing meshed separately; the
// filter takes it, and every step's crank-bearing faces (counted here by
// their point ids) are the Steps table's ContactFaces, none in the input.
TEST(AdaptAssembly, CrankInBearingFromData)
{
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((std::string(FEMORPH_DATA_DIR) + "/adapt/assembly_crank.vtu").c_str());
  reader->Update();
  vtkUnstructuredGrid* input = reader->GetOutput();
  ASSERT_GT(input->GetNumberOfCells(), 0);
  vtkNew<vtkFEMorphAdapt> filter;
  vtkNew<MessageRecorder> messages;
  messages->Observe(filter);
  filter->SetInputData(input);
  filter->SetMovingObject(1);
  filter->SetRotationAxis(0, 0, 1);
  filter->SetRotationCenter(0, 0, 0);
  filter->SetRotationAnglePerStep(10);
  filter->SetNumberOfSteps(3);
  const auto contactFaces = [](vtkUnstructuredGrid* mesh)
  {
    vtkDataArray* material = mesh->GetCellData()->GetArray("MaterialId");
    std::map<std::array<vtkIdType, 3>, std::vector<int>> faces;
    for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
    {
      vtkIdType npts = 0;
      const vtkIdType* pts = nullptr;
      mesh->GetCellPoints(c, npts, pts);
      for (int f = 0; f < 4; ++f)
      {
        std::array<vtkIdType, 3> key{ { pts[(f + 1) % 4], pts[(f + 2) % 4], pts[(f + 3) % 4] } };
        std::sort(key.begin(), key.end());
        faces[key].push_back(static_cast<int>(material->GetComponent(c, 0)));
      }
    }
    vtkIdType n = 0;
    for (const auto& entry : faces)
    {
      const std::vector<int>& m = entry.second;
      n += m.size() == 2 && std::min(m[0], m[1]) == 1 && std::max(m[0], m[1]) == 2;
    }
    return n;
  };
  ASSERT_EQ(RunAt(filter, 0), 1);
  EXPECT_EQ(contactFaces(filter->GetMeshOutput()), 0);
  for (int n = 1; n <= 3; ++n)
  {
    ASSERT_EQ(RunAt(filter, n), 1) << messages->AllErrors();
    vtkUnstructuredGrid* mesh = filter->GetMeshOutput();
    const vtkIdType faces = contactFaces(mesh);
    EXPECT_GT(faces, 0) << "step " << n;
    vtkTable* steps = filter->GetStepsOutput();
    ASSERT_EQ(steps->GetNumberOfRows(), n + 1);
    EXPECT_EQ(steps->GetColumnByName("ContactFaces")->GetVariantValue(n).ToLongLong(), faces) << "step " << n;
  }
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
}
