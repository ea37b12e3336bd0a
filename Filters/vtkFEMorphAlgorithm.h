/**
 * @class   vtkFEMorphAlgorithm
 * @brief   base class of every FEMorph filter: one RequestData skeleton
 *
 * Owns what every filter does the same way, so a filter's own file holds its
 * properties, their mapping to the core's options, the core call and its
 * outputs (docs/ARCHITECTURE.md, "Filters"):
 *
 * - input checks with one set of messages, on every connected input port:
 *   a missing input, a grid without points, points with NaN or infinite
 *   coordinates, cell types the filter does not read (InputCells), a point
 *   or cell array shorter than the points or cells, a cell with the wrong
 *   number of points for its type, a point id out of range, more points or
 *   cells than the core's 32-bit ids hold;
 * - one behaviour for an input without cells: every output empty and a
 *   warning (as VTK's filters do), the filter is not run;
 * - the core call inside try/catch (out of memory and other exceptions are
 *   errors naming the filter, never a crash), with a progress and abort
 *   callback (Progress(), ProgressRange()); an aborted or failed run leaves
 *   every output empty;
 * - conversion to and from the core mesh with the converter's warnings shown
 *   (vtkFEMorphMeshConversion), attribute transfer, and the field-data
 *   summary helpers (AddCount, AddValue, AddSummary, AddValues).
 *
 * Every message starts with the filter's label (e.g. "FEMorph Improve: "),
 * errors through vtkErrorMacro, warnings through vtkWarningMacro. The input
 * is never modified.
 *
 * A filter overrides CheckProperties() (NaN and cross-property checks; the
 * clamp macros let NaN through) and Execute(), and passes its label and the
 * cells it reads to the constructor.
 *
 * Parallel runs (pvbatch, pvserver under MPI; docs/ARCHITECTURE.md "Parallel
 * runs"): with the global controller's more than one process, a filter runs
 * in its GetPieceMode():
 * - Serial: each process runs the filter on its piece alone (as with one
 *   process);
 * - PerPiece: each process runs it on its piece; an empty piece is no
 *   error; the run goes on only when every piece passed the checks, and
 *   CombinePieces() then makes the field-data summaries global (the filter
 *   leaves ghost cells out of its counts);
 * - Gathered: every grid input's pieces go to process 0 without their ghost
 *   cells, with shared points merged (vtkFEMorphPieces::Gather; an input of
 *   another type, such as a table, is process 0's own); process 0
 *   runs the filter on the whole mesh and its outputs get global point and
 *   cell ids; the other processes output empty data.
 * With no controller or one process, every mode is the serial run.
 *
 * @sa vtkFEMorphMeshConversion
 */
#ifndef vtkFEMorphAlgorithm_h
#define vtkFEMorphAlgorithm_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <cstddef>    // For std::size_t
#include <functional> // For std::function
#include <string>     // For std::string
#include <utility>    // For std::pair
#include <vector>     // For std::vector

class vtkFieldData;
class vtkMultiProcessController;

namespace femorph
{
class TetMesh;
struct BuildOptions;
struct BuildReport;
struct CompactMesh;
struct Status;
}

class FEMORPHFILTERS_EXPORT vtkFEMorphAlgorithm : public vtkUnstructuredGridAlgorithm
{
public:
  vtkTypeMacro(vtkFEMorphAlgorithm, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The filter's name as ParaView shows it, e.g. "FEMorph Improve".
  const char* GetFilterLabel() const { return this->FilterLabel; }

  ///@{
  /// Field-data summary: one-tuple arrays (vtkIdTypeArray for counts,
  /// vtkDoubleArray otherwise); AddSummary names its components; AddValues
  /// is one tuple per value (e.g. per region).
  static void AddCount(vtkFieldData* fd, const std::string& name, vtkIdType value);
  static void AddValue(vtkFieldData* fd, const std::string& name, double value);
  static void AddSummary(vtkFieldData* fd, const std::string& name,
    const std::vector<std::pair<std::string, double>>& components);
  static void AddValues(vtkFieldData* fd, const std::string& name, const std::vector<double>& values);
  ///@}

  /// "1 point" / "3 points".
  static std::string Plural(std::size_t n, const char* one, const char* many);

protected:
  /// The cells a filter reads; anything else is an input error, with one
  /// message for all filters.
  enum InputCells
  {
    /// VTK_TETRA only.
    Tetrahedra,
    /// The linear 3D cells: tetrahedra, pyramids, wedges, hexahedra, voxels.
    Linear3DCells,
    /// Any cell (the filter handles the types it does not evaluate).
    AnyCells
  };

  /// How the filter runs on a distributed input (see the class documentation).
  enum PieceMode
  {
    Serial,
    PerPiece,
    Gathered
  };

  vtkFEMorphAlgorithm(const char* label, InputCells cells);
  ~vtkFEMorphAlgorithm() override;

  /// Every input port takes a vtkUnstructuredGrid; ports after the first are
  /// optional.
  int FillInputPortInformation(int port, vtkInformation* info) override;

  /// The skeleton (see the class documentation); filters override Execute().
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) final;

  /// Checks the properties before the input is read; reports every problem
  /// with Fail() and returns false on any.
  virtual bool CheckProperties() { return true; }

  /**
   * The filter's work on `input` (checked, with cells). Other input ports
   * and the outputs are read from the vectors. Returns false after
   * reporting an error with Fail(); the outputs are then cleared.
   */
  virtual bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) = 0;

  /// The filter's mode on a distributed input; Serial unless overridden.
  virtual PieceMode GetPieceMode() const { return Serial; }

  /**
   * PerPiece mode, more than one process: called on every process after
   * every piece's Execute() succeeded, to combine the outputs' summaries
   * over the processes with the controller's reductions (collective).
   */
  virtual void CombinePieces(vtkMultiProcessController*, vtkInformationVector*) {}

  /// How messages name input port `port`: "the input" for port 0, "the
  /// Reference input" for a port the filter names so.
  virtual std::string GetInputName(int port);

  ///@{
  /// Messages: `what` follows the filter's label and ": ".
  void Fail(const std::string& what);
  void Warn(const std::string& what);
  /// Fail() with the status's message unless it is ok; returns status.ok.
  bool Check(const femorph::Status& status);
  /// Warn() for each message.
  void WarnAll(const std::vector<std::string>& messages);
  ///@}

  /**
   * Fails with one message when `value` is not a number in [lo, hi] (NaN
   * included, which vtkSetClampMacro lets through). `meaning` (may be null)
   * follows the range in the message, e.g. "degrees".
   */
  bool CheckRange(const char* property, double value, double lo, double hi,
    const char* meaning = nullptr);

  ///@{
  /**
   * Progress and abort. Progress() shows `step` next to ParaView's progress
   * bar (null: unchanged) and returns false once the user aborted; the
   * skeleton then clears the outputs. ProgressRange() is the callback the
   * core's functions take: their fraction in [0, 1] maps to [begin, end].
   */
  bool Progress(double fraction, const char* step = nullptr);
  std::function<bool(double, const char*)> ProgressRange(double begin, double end);
  bool WasAborted() const { return this->Aborted; }
  ///@}

  ///@{
  /**
   * Conversion: `grid` (checked by the skeleton) into the core mesh with
   * `options` (face regions are the caller's, e.g. from
   * vtkFEMorphSegmentationArrays::ReadFromMesh), reporting the converter's
   * errors with Fail() and its warnings with Warn(). Returns false on error.
   */
  bool ToTetMesh(vtkUnstructuredGrid* grid, const femorph::BuildOptions& options,
    femorph::TetMesh& mesh, femorph::BuildReport* report = nullptr);
  /// The core mesh back into `output` with `source`'s attributes (the grid
  /// the mesh was built from): vtkFEMorphMeshConversion::FromCompactMesh().
  void FromCompactMesh(
    const femorph::CompactMesh& mesh, vtkUnstructuredGrid* source, vtkUnstructuredGrid* output);
  ///@}


private:
  vtkFEMorphAlgorithm(const vtkFEMorphAlgorithm&) = delete;
  void operator=(const vtkFEMorphAlgorithm&) = delete;

  /// The skeleton's checks of one input grid; reports with Fail().
  bool CheckInputGrid(vtkUnstructuredGrid* grid, int port);
  /// The checks of every connected input port (port 0 has cells).
  bool CheckInputs(vtkInformationVector** inputVector);
  /// Execute() inside try/catch; false on failure.
  bool RunExecute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector);
  /// The serial skeleton on the given inputs (RequestData's return value).
  int RunSerial(vtkInformationVector** inputVector, vtkInformationVector* outputVector);
  int RunPerPiece(vtkMultiProcessController* controller, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector);
  int RunGathered(vtkMultiProcessController* controller, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector);
  void ClearOutputs(vtkInformationVector* outputVector);

  const char* FilterLabel;
  InputCells Cells;
  bool Aborted = false;
};

#endif
