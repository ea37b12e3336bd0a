#include "vtkFEMorphAdapt.h"

#include "vtkFEMorphMeshConversion.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkDemandDrivenPipeline.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVariant.h"

#include "adapt/adapt.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkFEMorphAdapt);

//------------------------------------------------------------------------------
// The cache of computed steps: the working session, copies of it at some
// steps, the report of every step computed and the first step refused.
class vtkFEMorphAdapt::vtkInternals
{
public:
  struct Kept
  {
    femorph::AdaptSession Session;
    std::size_t Bytes = 0;
    /// The step's points with its point data (field transfer: step n's data
    /// is step n - 1's interpolated); null when the input has none.
    vtkSmartPointer<vtkUnstructuredGrid> Data;
  };

  /// What the cache was computed for (input, motion, properties).
  std::string Key;
  bool Initialized = false;
  femorph::AdaptSession Current;
  vtkSmartPointer<vtkUnstructuredGrid> CurrentData;
  std::map<int, Kept> Copies;
  /// Copies are kept at the steps that are multiples of Stride (and step 0).
  int Stride = 1;
  std::vector<femorph::AdaptStepReport> Reports;
  int FailedStep = -1;
  std::string FailMessage;

  void Clear()
  {
    this->Key.clear();
    this->Initialized = false;
    this->Current = femorph::AdaptSession();
    this->CurrentData = nullptr;
    this->Copies.clear();
    this->Stride = 1;
    this->Reports.clear();
    this->FailedStep = -1;
    this->FailMessage.clear();
  }

  std::size_t CopiesBytes() const
  {
    std::size_t bytes = 0;
    for (const auto& entry : this->Copies)
    {
      bytes += entry.second.Bytes;
    }
    return bytes;
  }

  /// Keeps a copy of the working session when its step is a multiple of
  /// Stride, then thins the copies to `limit` bytes.
  void Keep(std::size_t limit)
  {
    const int step = this->Current.current_step();
    if (step % this->Stride == 0)
    {
      const std::size_t data = this->CurrentData ? this->CurrentData->GetActualMemorySize() * 1024 : 0;
      this->Copies[step] = Kept{ this->Current, this->Current.memory_bytes() + data, this->CurrentData };
      this->Thin(limit);
    }
  }

  /// While the copies exceed `limit` bytes, Stride doubles and the copies
  /// off the new stride go (step 0 stays): the kept steps stay evenly spread
  /// over the steps computed, whatever their number.
  void Thin(std::size_t limit)
  {
    while (this->CopiesBytes() > limit && this->Copies.size() > 1)
    {
      this->Stride *= 2;
      for (auto it = this->Copies.begin(); it != this->Copies.end();)
      {
        it = (it->first != 0 && it->first % this->Stride != 0) ? this->Copies.erase(it) : std::next(it);
      }
    }
  }
};

namespace
{
/// The Motion table's column of matrix entry (r, c).
std::string MatrixColumn(int r, int c)
{
  return "m" + std::to_string(r) + std::to_string(c);
}

/// Rows 0..rows-1 of the Motion table as absolute poses. Fails naming the
/// missing column, or the row (as its 1-based step) and why it is not rigid.
femorph::Status ReadMotionTable(vtkTable* table, int rows, std::vector<femorph::RigidPose>& poses)
{
  poses.clear();
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      if (!table->GetColumnByName(MatrixColumn(r, c).c_str()))
      {
        return femorph::Status::failure("the Motion table has no column " + MatrixColumn(r, c) +
          "; it needs the columns m00, m01, ..., m33 (a 4x4 row-major matrix per step).");
      }
    }
  }
  for (int row = 0; row < rows; ++row)
  {
    double m[16];
    for (int k = 0; k < 16; ++k)
    {
      bool valid = false;
      const vtkVariant value = table->GetValueByName(row, MatrixColumn(k / 4, k % 4).c_str());
      m[k] = value.ToDouble(&valid);
      if (!valid)
      {
        return femorph::Status::failure("row " + std::to_string(row + 1) + " (step " +
          std::to_string(row + 1) + ") of the Motion table: " + MatrixColumn(k / 4, k % 4) +
          " is not a number ('" + value.ToString() + "').");
      }
    }
    femorph::RigidPose pose;
    const femorph::Status rigid = femorph::rigid_pose_from_matrix(m, pose);
    if (!rigid)
    {
      return femorph::Status::failure("row " + std::to_string(row + 1) + " (step " +
        std::to_string(row + 1) + ") of the Motion table is not a rigid motion: " + rigid.message + ".");
    }
    poses.push_back(pose);
  }
  return femorph::Status::success();
}

/// The mesh of a step from the session's output: the point data carried
/// step by step (`data`, null without point data), the input's cell data by
/// each tet's input cell.
void WriteStep(const femorph::AdaptOutput& out, vtkUnstructuredGrid* input, vtkUnstructuredGrid* data,
  const std::string& material, const femorph::AdaptStepReport& report, vtkUnstructuredGrid* output)
{
  output->SetPoints(vtkFEMorphMeshConversion::NewPoints(out.points));
  vtkFEMorphMeshConversion::SetTetCells(output, out.tets);
  if (data)
  {
    output->GetPointData()->ShallowCopy(data->GetPointData());
  }
  vtkFEMorphMeshConversion::CopySourceCellData(input, output, out.cell_origin);
  // The material as int, from the session (the copy above has the input's type).
  vtkCellData* cd = output->GetCellData();
  vtkDataArray* scalars = input->GetCellData()->GetScalars();
  const bool active = scalars && scalars->GetName() && material == scalars->GetName();
  cd->RemoveArray(material.c_str());
  vtkNew<vtkIntArray> ids;
  ids->SetName(material.c_str());
  ids->SetNumberOfValues(static_cast<vtkIdType>(out.material.size()));
  for (std::size_t t = 0; t < out.material.size(); ++t)
  {
    ids->SetValue(static_cast<vtkIdType>(t), out.material[t]);
  }
  cd->AddArray(ids);
  if (active)
  {
    cd->SetActiveScalars(material.c_str());
  }
  vtkFieldData* fd = output->GetFieldData();
  fd->PassData(input->GetFieldData());
  // What the step did (also a row of output 1).
  vtkFEMorphAlgorithm::AddCount(fd, "AdaptStep", report.step);
  vtkFEMorphAlgorithm::AddSummary(
    fd, "AdaptStretch", { { "Min", report.min_stretch }, { "Mean", report.mean_stretch } });
  vtkFEMorphAlgorithm::AddCount(fd, "AdaptDeformedRegionTets", static_cast<vtkIdType>(report.deformed_region_tets));
  vtkFEMorphAlgorithm::AddCount(fd, "AdaptSubsteps", report.substeps);
}

/// Output 1: one row per step report.
void WriteSteps(const std::vector<femorph::AdaptStepReport>& reports, int last, vtkTable* table)
{
  vtkNew<vtkIntArray> step, substeps;
  vtkNew<vtkIdTypeArray> vertices, tets, region, contact, inner;
  vtkNew<vtkDoubleArray> minStretch, meanStretch, seconds;
  step->SetName("Step");
  vertices->SetName("Vertices");
  tets->SetName("Tetrahedra");
  minStretch->SetName("MinStretch");
  meanStretch->SetName("MeanStretch");
  region->SetName("DeformedRegionTets");
  contact->SetName("ContactFaces");
  seconds->SetName("Seconds");
  substeps->SetName("Substeps");
  inner->SetName("InnerVertices");
  for (int n = 0; n <= last && n < static_cast<int>(reports.size()); ++n)
  {
    const femorph::AdaptStepReport& r = reports[static_cast<std::size_t>(n)];
    step->InsertNextValue(n);
    vertices->InsertNextValue(static_cast<vtkIdType>(r.vertices));
    tets->InsertNextValue(static_cast<vtkIdType>(r.tets));
    minStretch->InsertNextValue(r.min_stretch);
    meanStretch->InsertNextValue(r.mean_stretch);
    region->InsertNextValue(static_cast<vtkIdType>(r.deformed_region_tets));
    contact->InsertNextValue(static_cast<vtkIdType>(r.contact_faces));
    seconds->InsertNextValue(r.seconds);
    substeps->InsertNextValue(r.substeps);
    inner->InsertNextValue(static_cast<vtkIdType>(r.inner_vertices));
  }
  for (vtkAbstractArray* column : std::initializer_list<vtkAbstractArray*>{ step, vertices, tets,
         minStretch, meanStretch, region, contact, seconds, substeps, inner })
  {
    table->AddColumn(column);
  }
}
}

//------------------------------------------------------------------------------
vtkFEMorphAdapt::vtkFEMorphAdapt()
  : vtkFEMorphAlgorithm("FEMorph Adapt", Tetrahedra)
  , Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
  const femorph::AdaptOptions options;
  this->MovingObject = options.moving_object;
  this->DistanceThreshold = options.distance_threshold;
  this->GridCellSize = options.grid_cell_size;
  this->Improve = options.improve;
}

vtkFEMorphAdapt::~vtkFEMorphAdapt() = default;

//------------------------------------------------------------------------------
void vtkFEMorphAdapt::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const auto vec = [&os](const double v[3]) { os << v[0] << " " << v[1] << " " << v[2] << "\n"; };
  os << indent << "MaterialArray: " << this->MaterialArray << "\n";
  os << indent << "MovingObject: " << this->MovingObject << "\n";
  os << indent << "TranslationPerStep: ";
  vec(this->TranslationPerStep);
  os << indent << "RotationAxis: ";
  vec(this->RotationAxis);
  os << indent << "RotationCenter: ";
  vec(this->RotationCenter);
  os << indent << "RotationAnglePerStep: " << this->RotationAnglePerStep << "\n";
  os << indent << "NumberOfSteps: " << this->NumberOfSteps << "\n";
  os << indent << "DistanceThreshold: " << this->DistanceThreshold << "\n";
  os << indent << "GridCellSize: " << this->GridCellSize << "\n";
  os << indent << "Improve: " << this->Improve << "\n";
  os << indent << "QualityFloor: " << this->QualityFloor << "\n";
  os << indent << "CacheMemoryLimit: " << this->CacheMemoryLimit << "\n";
  os << indent << "ComputedSteps: " << this->ComputedSteps << "\n";
  os << indent << "CachedSteps: " << this->GetNumberOfCachedSteps() << "\n";
}

int vtkFEMorphAdapt::GetNumberOfCachedSteps() const
{
  return static_cast<int>(this->Internals->Copies.size());
}

vtkUnstructuredGrid* vtkFEMorphAdapt::GetMeshOutput()
{
  return vtkUnstructuredGrid::SafeDownCast(this->GetOutputDataObject(0));
}

vtkTable* vtkFEMorphAdapt::GetStepsOutput()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

std::string vtkFEMorphAdapt::GetInputName(int port)
{
  return port == 1 ? "the Motion input" : this->Superclass::GetInputName(port);
}

//------------------------------------------------------------------------------
int vtkFEMorphAdapt::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

int vtkFEMorphAdapt::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 1 ? "vtkTable" : "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkFEMorphAdapt::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The time of the port that asked is the step to produce.
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA()))
  {
    const int port = request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
      ? request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
      : 0;
    this->RequestedPort = port >= 0 && port < this->GetNumberOfOutputPorts() ? port : 0;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkFEMorphAdapt::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The steps are the output's time steps 0..N, so that ParaView's animation
  // plays them. The Motion table's rows cap N: it is brought up to date here
  // (a small table), since its row count is data, not information.
  int steps = this->NumberOfSteps;
  if (this->GetNumberOfInputConnections(1) > 0)
  {
    vtkAlgorithmOutput* connection = this->GetInputConnection(1, 0);
    if (connection && connection->GetProducer())
    {
      connection->GetProducer()->Update(connection->GetIndex());
    }
    vtkTable* table = vtkTable::GetData(inputVector[1], 0);
    steps = std::min<vtkIdType>(steps, table ? table->GetNumberOfRows() : 0);
  }
  std::vector<double> times(static_cast<std::size_t>(steps) + 1);
  for (std::size_t n = 0; n < times.size(); ++n)
  {
    times[n] = static_cast<double>(n);
  }
  const double range[2] = { 0, static_cast<double>(steps) };
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  return 1;
}

int vtkFEMorphAdapt::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  // The requested time is the motion step, not a time of the inputs: they
  // are read as they are, so that scrubbing does not change them.
  for (int port = 0; port < this->GetNumberOfInputPorts(); ++port)
  {
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      inputVector[port]->GetInformationObject(i)->Remove(
        vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkFEMorphAdapt::CheckProperties()
{
  if (!(this->CheckRange("DistanceThreshold", this->DistanceThreshold, 1, 100, "grid cells") &&
        this->CheckRange("GridCellSize", this->GridCellSize, 0, 1e30, "0: automatic") &&
        this->CheckRange("QualityFloor", this->QualityFloor, 0, 0.6, "0: automatic") &&
        this->CheckRange("RotationAnglePerStep", this->RotationAnglePerStep, -360, 360, "degrees")))
  {
    return false;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (!std::isfinite(this->TranslationPerStep[k]) || !std::isfinite(this->RotationAxis[k]) ||
      !std::isfinite(this->RotationCenter[k]))
    {
      this->Fail("TranslationPerStep, RotationAxis and RotationCenter must be finite.");
      return false;
    }
  }
  const double axis = std::sqrt(this->RotationAxis[0] * this->RotationAxis[0] +
    this->RotationAxis[1] * this->RotationAxis[1] + this->RotationAxis[2] * this->RotationAxis[2]);
  if (this->RotationAnglePerStep != 0 && !(axis > 0))
  {
    this->Fail("RotationAxis is (0, 0, 0), but RotationAnglePerStep is not 0: a rotation needs an axis.");
    return false;
  }
  if (this->MaterialArray.empty())
  {
    this->Fail("MaterialArray is empty: name the cell array of material ids (0 space, k > 0 object k).");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkFEMorphAdapt::Execute(
  vtkUnstructuredGrid* input, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkTable* stepsOutput = vtkTable::GetData(outputVector, 1);
  vtkInternals& cache = *this->Internals;

  // The material and the motion.
  std::vector<int> material;
  if (!this->Check(
        vtkFEMorphMeshConversion::ReadCellIds(input, this->MaterialArray, "MaterialArray", material)))
  {
    return false;
  }
  if (std::find(material.begin(), material.end(), this->MovingObject) == material.end())
  {
    const std::set<int> present(material.begin(), material.end());
    std::ostringstream ids;
    int listed = 0;
    for (auto it = present.begin(); it != present.end() && listed < 20; ++it, ++listed)
    {
      ids << (listed ? ", " : "") << *it;
    }
    this->Fail("no cell has the MovingObject id " + std::to_string(this->MovingObject) + " in '" +
      this->MaterialArray + "' (its ids: " + ids.str() + (present.size() > 20 ? ", ..." : "") + ").");
    return false;
  }
  femorph::RigidMotion motion;
  motion.translation_per_step =
    femorph::Vec3(this->TranslationPerStep[0], this->TranslationPerStep[1], this->TranslationPerStep[2]);
  motion.rotation_axis = femorph::Vec3(this->RotationAxis[0], this->RotationAxis[1], this->RotationAxis[2]);
  motion.rotation_center =
    femorph::Vec3(this->RotationCenter[0], this->RotationCenter[1], this->RotationCenter[2]);
  motion.rotation_degrees_per_step = this->RotationAnglePerStep;
  int steps = this->NumberOfSteps;
  vtkTable* table = vtkTable::GetData(inputVector[1], 0);
  if (this->GetNumberOfInputConnections(1) > 0)
  {
    if (!table || table->GetNumberOfRows() == 0)
    {
      this->Fail("the Motion table has no rows: one 4x4 pose (columns m00..m33) per step is needed.");
      return false;
    }
    // Every row, so that the motion (and the cache) does not depend on
    // NumberOfSteps.
    const vtkIdType rows = table->GetNumberOfRows();
    if (rows > 1000000)
    {
      this->Fail(
        "the Motion table has " + std::to_string(rows) + " rows; at most 1000000 steps are supported.");
      return false;
    }
    if (!this->Check(ReadMotionTable(table, static_cast<int>(rows), motion.table)))
    {
      return false;
    }
    steps = static_cast<int>(std::min<vtkIdType>(steps, rows));
  }
  else
  {
    table = nullptr;
  }

  // The step asked for: the requested time rounded to the nearest step.
  double time = 0;
  for (const int port : { this->RequestedPort, 0, 1 })
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    if (info && info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      time = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
      break;
    }
  }
  const int requested = std::isfinite(time)
    ? static_cast<int>(std::min<double>(std::max(std::round(time), 0.0), steps))
    : 0;

  // The cache holds for this input, motion and properties (NumberOfSteps
  // and CacheMemoryLimit do not change the steps).
  std::ostringstream key;
  key.precision(17);
  key << input << " " << input->GetMTime() << " " << table << " " << (table ? table->GetMTime() : 0) << " "
      << this->MaterialArray << " " << this->MovingObject << " " << motion.translation_per_step.transpose()
      << " " << motion.rotation_axis.transpose() << " " << motion.rotation_center.transpose() << " "
      << this->RotationAnglePerStep << " " << this->DistanceThreshold << " " << this->GridCellSize << " "
      << this->Improve << " " << this->QualityFloor;
  if (cache.Key != key.str())
  {
    cache.Clear();
  }
  const std::size_t limit = static_cast<std::size_t>(this->CacheMemoryLimit) * 1024 * 1024;
  if (!cache.Initialized)
  {
    this->Progress(0.0, "preparing the adaptation");
    std::vector<femorph::Vec3> points;
    std::vector<femorph::Tet> tets;
    if (!this->Check(vtkFEMorphMeshConversion::ReadTetGrid(input, points, tets)))
    {
      return false;
    }
    femorph::AdaptOptions options;
    options.moving_object = this->MovingObject;
    options.grid_cell_size = this->GridCellSize;
    options.distance_threshold = this->DistanceThreshold;
    options.improve = this->Improve != 0;
    options.quality_floor = this->QualityFloor;
    const femorph::Status ready = cache.Current.init(points, tets, material, motion, options);
    if (!ready)
    {
      cache.Clear();
      this->Fail(ready.message + ".");
      return false;
    }
    cache.Key = key.str();
    cache.Initialized = true;
    cache.Reports.assign(1, cache.Current.initial_report());
    if (input->GetPointData()->GetNumberOfArrays() > 0)
    {
      cache.CurrentData = vtkSmartPointer<vtkUnstructuredGrid>::New();
      cache.CurrentData->SetPoints(input->GetPoints());
      cache.CurrentData->GetPointData()->ShallowCopy(input->GetPointData());
    }
    cache.Copies[0] = vtkInternals::Kept{ cache.Current, cache.Current.memory_bytes(), cache.CurrentData };
  }
  else
  {
    // CacheMemoryLimit may have been lowered.
    cache.Thin(limit);
  }

  // A refused step ends the motion: later times show the last good step.
  int target = requested;
  if (cache.FailedStep > 0 && target >= cache.FailedStep)
  {
    target = cache.FailedStep - 1;
  }
  const femorph::AdaptSession* session = nullptr;
  vtkUnstructuredGrid* data = nullptr;
  if (cache.Current.current_step() == target)
  {
    session = &cache.Current;
    data = cache.CurrentData;
  }
  else if (cache.Copies.count(target))
  {
    session = &cache.Copies[target].Session;
    data = cache.Copies[target].Data;
  }
  else
  {
    // From the nearest step before the target: the working session when it
    // is nearer than every copy, else the nearest copy.
    auto nearest = std::prev(cache.Copies.upper_bound(target));
    const int now = cache.Current.current_step();
    if (!(now <= target && now > nearest->first))
    {
      cache.Current = nearest->second.Session;
      cache.CurrentData = nearest->second.Data;
    }
    const int first = cache.Current.current_step();
    while (cache.Current.current_step() < target)
    {
      const int next = cache.Current.current_step() + 1;
      const std::string text = "step " + std::to_string(next) + " of " + std::to_string(steps);
      if (!this->Progress(static_cast<double>(next - 1 - first) / (target - first), text.c_str()))
      {
        return true;
      }
      femorph::AdaptStepReport report;
      const femorph::Status advanced = cache.Current.advance(&report);
      if (!advanced)
      {
        cache.FailedStep = next;
        cache.FailMessage = advanced.message;
        target = cache.Current.current_step();
        break;
      }
      ++this->ComputedSteps;
      if (cache.CurrentData)
      {
        // Field transfer: the previous step's point data at the new points.
        const femorph::AdaptOutput out = cache.Current.output();
        vtkNew<vtkUnstructuredGrid> data;
        data->SetPoints(vtkFEMorphMeshConversion::NewPoints(out.points));
        vtkFEMorphMeshConversion::InterpolatePointData(cache.CurrentData, out.point_previous, data);
        cache.CurrentData = data.Get();
      }
      report.step = next;
      if (static_cast<std::size_t>(next) == cache.Reports.size())
      {
        this->WarnAll(report.warnings);
        cache.Reports.push_back(report);
      }
      cache.Keep(limit);
    }
    session = &cache.Current;
    data = cache.CurrentData;
  }
  if (cache.FailedStep > 0 && requested >= cache.FailedStep)
  {
    // The core's message names the step; say it when it does not.
    const std::string step = "step " + std::to_string(cache.FailedStep);
    std::string message = cache.FailMessage;
    const std::size_t at = message.find(step), after = at + step.size();
    const bool named = at != std::string::npos &&
      (after == message.size() || !std::isdigit(static_cast<unsigned char>(message[after])));
    if (!message.empty() && message.back() == '.')
    {
      message.pop_back();
    }
    this->Fail((named ? "" : step + " was refused: ") + message + ". The output for time " +
      std::to_string(cache.FailedStep) + " and later is the mesh of step " +
      std::to_string(cache.FailedStep - 1) + ", the last one computed.");
  }

  this->Progress(1.0, "writing the output");
  if (target == 0)
  {
    // Step 0 is the input as it is.
    output->ShallowCopy(input);
  }
  else
  {
    femorph::AdaptStepReport report;
    report.step = target;
    if (static_cast<std::size_t>(target) < cache.Reports.size())
    {
      report = cache.Reports[static_cast<std::size_t>(target)];
    }
    WriteStep(session->output(), input, data, this->MaterialArray, report, output);
  }
  WriteSteps(cache.Reports, target, stepsOutput);
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    if (vtkDataObject* data = vtkDataObject::GetData(outputVector, port))
    {
      data->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), static_cast<double>(requested));
    }
  }
  return true;
}
