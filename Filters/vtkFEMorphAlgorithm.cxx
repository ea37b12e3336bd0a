#include "vtkFEMorphAlgorithm.h"

#include "vtkFEMorphMeshConversion.h"
#include "vtkFEMorphPieces.h"

#include "vtkCommunicator.h"
#include "vtkDataSet.h"
#include "vtkMultiProcessController.h"
#include "vtkSmartPointer.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkUnstructuredGrid.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <new>
#include <sstream>

//------------------------------------------------------------------------------
vtkFEMorphAlgorithm::vtkFEMorphAlgorithm(const char* label, InputCells cells)
  : FilterLabel(label)
  , Cells(cells)
{
}

vtkFEMorphAlgorithm::~vtkFEMorphAlgorithm() = default;

//------------------------------------------------------------------------------
void vtkFEMorphAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FilterLabel: " << this->FilterLabel << "\n";
}

//------------------------------------------------------------------------------
int vtkFEMorphAlgorithm::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  if (port > 0)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
std::string vtkFEMorphAlgorithm::GetInputName(int port)
{
  return port == 0 ? "the input" : "input " + std::to_string(port);
}

//------------------------------------------------------------------------------
void vtkFEMorphAlgorithm::Fail(const std::string& what)
{
  vtkErrorMacro(<< this->FilterLabel << ": " << what);
}

void vtkFEMorphAlgorithm::Warn(const std::string& what)
{
  vtkWarningMacro(<< this->FilterLabel << ": " << what);
}

bool vtkFEMorphAlgorithm::Check(const femorph::Status& status)
{
  if (!status.ok)
  {
    this->Fail(status.message);
  }
  return status.ok;
}

void vtkFEMorphAlgorithm::WarnAll(const std::vector<std::string>& messages)
{
  for (const std::string& message : messages)
  {
    this->Warn(message);
  }
}

//------------------------------------------------------------------------------
bool vtkFEMorphAlgorithm::CheckRange(
  const char* property, double value, double lo, double hi, const char* meaning)
{
  if (value >= lo && value <= hi)
  {
    return true;
  }
  std::ostringstream os;
  os << property << " must be a number in [" << lo << ", " << hi << "]"
     << (meaning ? std::string(" (") + meaning + ")" : std::string()) << "; it is " << value << ".";
  this->Fail(os.str());
  return false;
}

//------------------------------------------------------------------------------
bool vtkFEMorphAlgorithm::Progress(double fraction, const char* step)
{
  if (step)
  {
    this->SetProgressText(step);
  }
  this->UpdateProgress(std::min(std::max(fraction, 0.0), 1.0));
  this->Aborted = this->Aborted || this->CheckAbort();
  return !this->Aborted;
}

std::function<bool(double, const char*)> vtkFEMorphAlgorithm::ProgressRange(double begin, double end)
{
  return [this, begin, end](double fraction, const char* step) {
    return this->Progress(begin + (end - begin) * std::min(std::max(fraction, 0.0), 1.0), step);
  };
}

//------------------------------------------------------------------------------
bool vtkFEMorphAlgorithm::ToTetMesh(vtkUnstructuredGrid* grid,
  const femorph::BuildOptions& options, femorph::TetMesh& mesh, femorph::BuildReport* report)
{
  std::vector<std::string> warnings;
  const femorph::Status status =
    vtkFEMorphMeshConversion::ToTetMesh(grid, options, mesh, report, &warnings);
  this->WarnAll(warnings);
  return this->Check(status);
}

void vtkFEMorphAlgorithm::FromCompactMesh(
  const femorph::CompactMesh& mesh, vtkUnstructuredGrid* source, vtkUnstructuredGrid* output)
{
  vtkFEMorphMeshConversion::FromCompactMesh(mesh, source, output);
}

//------------------------------------------------------------------------------
void vtkFEMorphAlgorithm::AddCount(vtkFieldData* fd, const std::string& name, vtkIdType value)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

void vtkFEMorphAlgorithm::AddValue(vtkFieldData* fd, const std::string& name, double value)
{
  AddValues(fd, name, { value });
}

void vtkFEMorphAlgorithm::AddSummary(vtkFieldData* fd, const std::string& name,
  const std::vector<std::pair<std::string, double>>& components)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfComponents(static_cast<int>(components.size()));
  a->SetNumberOfTuples(1);
  for (std::size_t i = 0; i < components.size(); ++i)
  {
    a->SetComponentName(static_cast<vtkIdType>(i), components[i].first.c_str());
    a->SetTypedComponent(0, static_cast<int>(i), components[i].second);
  }
  fd->AddArray(a);
}

void vtkFEMorphAlgorithm::AddValues(
  vtkFieldData* fd, const std::string& name, const std::vector<double>& values)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    a->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  fd->AddArray(a);
}

std::string vtkFEMorphAlgorithm::Plural(std::size_t n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

//------------------------------------------------------------------------------
bool vtkFEMorphAlgorithm::CheckInputGrid(vtkUnstructuredGrid* grid, int port)
{
  vtkFEMorphMeshConversion::CellSet cells = vtkFEMorphMeshConversion::CellSet::Any;
  switch (this->Cells)
  {
    case Tetrahedra: cells = vtkFEMorphMeshConversion::CellSet::Tetrahedra; break;
    case Linear3DCells: cells = vtkFEMorphMeshConversion::CellSet::Linear3D; break;
    case AnyCells: break;
  }
  const std::string problem =
    vtkFEMorphMeshConversion::CheckGrid(grid, cells, this->GetInputName(port));
  if (!problem.empty())
  {
    this->Fail(problem);
    return false;
  }
  return true;
}

void vtkFEMorphAlgorithm::ClearOutputs(vtkInformationVector* outputVector)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    if (vtkDataObject* output = vtkDataObject::GetData(outputVector, port))
    {
      output->Initialize();
    }
  }
}

//------------------------------------------------------------------------------
bool vtkFEMorphAlgorithm::CheckInputs(vtkInformationVector** inputVector)
{
  for (int port = 0; port < this->GetNumberOfInputPorts(); ++port)
  {
    vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(inputVector[port], 0);
    // An optional input without cells counts as absent (the filter says so).
    if (grid && (port == 0 || grid->GetNumberOfCells() > 0) && !this->CheckInputGrid(grid, port))
    {
      return false;
    }
  }
  return true;
}

bool vtkFEMorphAlgorithm::RunExecute(
  vtkUnstructuredGrid* input, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->UpdateProgress(0.0);
  try
  {
    return this->Execute(input, inputVector, outputVector);
  }
  catch (const std::bad_alloc&)
  {
    this->Fail("out of memory (" +
      Plural(static_cast<std::size_t>(input->GetNumberOfCells()), "cell", "cells") +
      " in the input).");
  }
  catch (const std::exception& e)
  {
    this->Fail(std::string("failed: ") + e.what());
  }
  return false;
}

//------------------------------------------------------------------------------
int vtkFEMorphAlgorithm::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Aborted = false;
  this->ClearOutputs(outputVector);
  // The step names shown next to the progress bar end with this request.
  struct ClearProgressText
  {
    vtkAlgorithm* Algorithm;
    ~ClearProgressText() { this->Algorithm->SetProgressText(nullptr); }
  } clearProgressText{ this };

  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    switch (this->GetPieceMode())
    {
      case PerPiece: return this->RunPerPiece(controller, inputVector, outputVector);
      case Gathered: return this->RunGathered(controller, inputVector, outputVector);
      case Serial: break;
    }
  }
  return this->RunSerial(inputVector, outputVector);
}

int vtkFEMorphAlgorithm::RunSerial(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  if (!input)
  {
    this->Fail("needs a vtkUnstructuredGrid input.");
    return 0;
  }
  if (input->GetNumberOfCells() == 0)
  {
    this->Warn(GetInputName(0) + " has no cells (" +
      Plural(static_cast<std::size_t>(input->GetNumberOfPoints()), "point", "points") +
      "); the output is empty.");
    return 1;
  }
  if (!this->CheckProperties() || !this->CheckInputs(inputVector))
  {
    return 0;
  }
  const bool ok = this->RunExecute(input, inputVector, outputVector);
  if (this->Aborted || !ok)
  {
    this->ClearOutputs(outputVector);
    return this->Aborted ? 1 : 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphAlgorithm::RunPerPiece(vtkMultiProcessController* controller,
  vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Every process takes each collective step, whatever its piece: the
  // decisions to go on are reductions, so no process waits for another
  // that stopped.
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
  const bool propertiesOk = this->CheckProperties(); // same on every process
  const vtkIdType localCells = input ? input->GetNumberOfCells() : 0;
  const int localOk = input && (localCells == 0 || this->CheckInputs(inputVector)) ? 1 : 0;
  long long cellsAndBad[2] = { static_cast<long long>(localCells), localOk ? 0 : 1 };
  long long global[2] = { 0, 0 };
  controller->AllReduce(cellsAndBad, global, 2, vtkCommunicator::SUM_OP);
  if (!propertiesOk)
  {
    return 0;
  }
  if (global[1] > 0)
  {
    if (localOk)
    {
      this->Fail("the piece of " + Plural(static_cast<std::size_t>(global[1]), "other process",
        "other processes") + " was refused (see its message); the output is empty.");
    }
    return 0;
  }
  if (global[0] == 0)
  {
    if (controller->GetLocalProcessId() == 0)
    {
      this->Warn(GetInputName(0) + " has no cells on any process; the output is empty.");
    }
    return 1;
  }
  // An empty piece runs too: its Execute() gives an empty output and
  // neutral summaries for the reductions.
  const int ok = this->RunExecute(input, inputVector, outputVector) && !this->Aborted ? 1 : 0;
  int allOk = 0;
  controller->AllReduce(&ok, &allOk, 1, vtkCommunicator::MIN_OP);
  if (!allOk)
  {
    this->ClearOutputs(outputVector);
    return this->Aborted ? 1 : 0;
  }
  this->CombinePieces(controller, outputVector);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkFEMorphAlgorithm::RunGathered(vtkMultiProcessController* controller,
  vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Each connected input's pieces on process 0 (a port is connected on every
  // process or on none: the pipeline is the same).
  const int numPorts = this->GetNumberOfInputPorts();
  const bool root = controller->GetLocalProcessId() == 0;
  std::vector<vtkSmartPointer<vtkInformationVector>> gathered(static_cast<std::size_t>(numPorts));
  std::vector<vtkInformationVector*> vectors(static_cast<std::size_t>(numPorts));
  for (int port = 0; port < numPorts; ++port)
  {
    auto& vector = gathered[static_cast<std::size_t>(port)];
    vector = vtkSmartPointer<vtkInformationVector>::New();
    vectors[static_cast<std::size_t>(port)] = vector;
    if (inputVector[port]->GetNumberOfInformationObjects() == 0)
    {
      continue;
    }
    // A port of another type (Adapt's Motion table) is the same on every
    // process or read by process 0 alone: process 0 keeps its own.
    vtkDataObject* data = vtkDataObject::GetData(inputVector[port], 0);
    if (!vtkUnstructuredGrid::SafeDownCast(data))
    {
      vector = inputVector[port];
      vectors[static_cast<std::size_t>(port)] = vector;
      continue;
    }
    vtkSmartPointer<vtkUnstructuredGrid> merged =
      vtkFEMorphPieces::Gather(controller, vtkUnstructuredGrid::SafeDownCast(data));
    if (root)
    {
      vtkNew<vtkInformation> info;
      info->Set(vtkDataObject::DATA_OBJECT(), merged);
      vector->Append(info);
    }
  }
  if (!root)
  {
    return 1;
  }
  const int result = this->RunSerial(vectors.data(), outputVector);
  if (result && !this->Aborted)
  {
    for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
    {
      vtkFEMorphPieces::AddGlobalIds(vtkDataSet::GetData(outputVector, port));
    }
  }
  return result;
}
