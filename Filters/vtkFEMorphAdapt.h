/**
 * @class   vtkFEMorphAdapt
 * @brief   moves one rigid object through a tetrahedral assembly mesh step
 *          by step, adapting only the space elements near it; each step is a
 *          time step of the output
 *
 * ParaView: "FEMorph Adapt" (menu FEMorph). Thesis chapter 3: the mesh holds
 * the space (material 0) and objects (material k > 0) conformally; per step
 * the moving object is transformed rigidly, the deformed region K_Df of space
 * tetrahedra near it (3.4.3: within DistanceThreshold cells of the distance
 * grid G_d that moves with the object) is re-embedded by 3D mean value
 * coordinates (3.5.3, Eqs. 3.1-3.2) and improved by FEMorph Improve's core
 * (3.6); the rest of the mesh does not change. A step that would invert
 * tetrahedra is split into sub-steps. Contact (3.4.2, 3.5.2, 3.5.4-3.5.5,
 * 3.7.3): objects that touch or slide on each other along the same analytic
 * surface (plane, cylinder, cone, sphere, torus) get a conformal contact
 * surface each step (every contact triangle a face of one tetrahedron of
 * each object), also when they touch in the input. An input without
 * space cells (no material 0) is an assembly of parts meshed separately
 * (3.7.4): their touching surfaces need not be conformal; each step makes
 * the moving part's contacts conformal and moves the rest of it rigidly.
 * Not supported yet: contacts wrapping all around a surface (a shaft in a
 * full hole). The algorithm is femorph_core's AdaptSession
 * (Core/adapt/adapt.h).
 *
 * Input 0: VTK_TETRA cells with the integer cell array MaterialArray
 * (default "MaterialId", one component, values >= 0): 0 is the space mesh,
 * k > 0 object k. With a space mesh, the moving object (MovingObject) must
 * not touch the domain's outer boundary. Without one (an assembly, 3.7.4),
 * the parts' surfaces are the domain's boundary, and parts must not
 * overlap (touching is fine). The input is never modified, and its own time
 * steps are not requested (this filter's time is the motion step).
 *
 * Input 1 (optional, "Motion"): a vtkTable with the numeric columns m00, m01,
 * ..., m33, one 4x4 row-major matrix per row: row n - 1 is the absolute pose
 * (from the input's position) of the object at step n. It replaces
 * TranslationPerStep, RotationAxis, RotationCenter and RotationAnglePerStep,
 * and the steps are at most its rows. Every row is read (the motion does
 * not depend on NumberOfSteps): one that is not a rigid motion (scaling,
 * shear, reflection, a last row other than 0 0 0 1) or not numeric is an
 * error naming the row and its step. The table is updated while the time
 * steps are reported (RequestInformation), since its rows cap them.
 *
 * Properties:
 * - MaterialArray ("MaterialId"), MovingObject (1): the object that moves.
 * - TranslationPerStep (0 0 0), RotationAxis (1 0 0), RotationCenter
 *   (0 0 0), RotationAnglePerStep (0, degrees): the pose of step n maps x to
 *   c + n t + R(axis, n angle) (x - c).
 * - NumberOfSteps (10): the output's time steps are 0, 1, ..., NumberOfSteps
 *   (step 0 is the input, unchanged).
 * - DistanceThreshold (3, cells of G_d; thesis 3.4.3 delta_dist): how far
 *   from the object the space is adapted.
 * - GridCellSize (0): edge of the grids G_d and G_v (3.4.1); 0: automatic
 *   (6 x the largest displacement of an object point in one step, at least
 *   the mean edge length).
 * - Improve (on): quality improvement of the deformed region every step
 *   (3.6); QualityFloor (0): its floor (stretch; 0: automatic, 1.1 x the
 *   input's minimum stretch within [0.1, 0.4]).
 * - CacheMemoryLimit (1024 MB): the computed steps are kept as copies of
 *   the session, within this bound (see below).
 *
 * Time: RequestData rounds the requested time to the nearest step (clamped
 * to 0..NumberOfSteps). Steps are computed in order and cached: copies of
 * the session at every k-th step, k doubled while the copies exceed
 * CacheMemoryLimit (step 0 is always kept). A step before the last one
 * computed is recomputed from the nearest kept step before it, never from
 * step 0 when a nearer one is kept. Changing any property but NumberOfSteps
 * and CacheMemoryLimit, the input or the motion table clears the cache.
 * GetComputedSteps() counts the steps computed since the filter was made.
 * Progress is reported per step; an abort (checked between steps) leaves
 * the outputs empty and keeps the steps done for the next request.
 *
 * Output 0 ("Mesh"): the mesh of the requested step (step 0: the input
 * itself, shallow-copied); from step 1: VTK_TETRA cells, the
 * cell array MaterialArray (int), every cell array of the input copied from
 * the input cell each tetrahedron descends from, every point array of the
 * input carried step by step (field transfer: at the object's points it
 * moves with the object, at the space points the previous step's field is
 * interpolated at their new position; integer arrays take the value of the
 * largest weight), the input's field data, and (from step 1) a summary in
 * field data: AdaptStep, AdaptStretch (Min, Mean), AdaptDeformedRegionTets,
 * AdaptSubsteps.
 *
 * Output 1 ("Steps"): a vtkTable, one row per step 0..requested step:
 * Step, Vertices, Tetrahedra, MinStretch, MeanStretch, DeformedRegionTets
 * (K_Df, summed over sub-steps), ContactFaces (faces shared by tetrahedra
 * of two different objects after the step), Seconds, Substeps,
 * InnerVertices (unknowns of Eq. 3.2, summed over sub-steps).
 *
 * Errors (empty outputs): no MaterialArray, an array that is not an integer
 * one-component cell array, a negative id, no cell of MovingObject, an
 * object whose interface with the space is not conformal, an assembly (no
 * space cell) of one part or whose parts overlap, a motion-table row that
 * is not rigid or columns missing. A step the
 * core refuses (the object would penetrate the boundary or another object,
 * or the space between collapse) is an error naming the step; the outputs
 * for that and every later time are then the last step computed, and the
 * message says so.
 *
 * @warning Each piece is adapted on its own: in a distributed run the
 * partition boundaries would be fixed like the outer boundary, and a piece
 * without the object is an error. Run it on one process. The cached steps
 * hold whole copies of the mesh: CacheMemoryLimit bounds them.
 *
 * @sa vtkFEMorphImprove, vtkFEMorphDeform
 */
#ifndef vtkFEMorphAdapt_h
#define vtkFEMorphAdapt_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkTable;

class FEMORPHFILTERS_EXPORT vtkFEMorphAdapt : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphAdapt* New();
  vtkTypeMacro(vtkFEMorphAdapt, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Cell array of material ids (0 space, k > 0 object k). Default "MaterialId".
  vtkSetStdStringFromCharMacro(MaterialArray);
  vtkGetCharFromStdStringMacro(MaterialArray);
  ///@}

  ///@{
  /// Material id of the object that moves. Default 1.
  vtkSetClampMacro(MovingObject, int, 1, VTK_INT_MAX);
  vtkGetMacro(MovingObject, int);
  ///@}

  ///@{
  /// The motion per step (ignored when the Motion table is connected):
  /// translation (model units), rotation axis, a point on it, and angle
  /// (degrees). Defaults 0 0 0, 1 0 0, 0 0 0 and 0.
  vtkSetVector3Macro(TranslationPerStep, double);
  vtkGetVector3Macro(TranslationPerStep, double);
  vtkSetVector3Macro(RotationAxis, double);
  vtkGetVector3Macro(RotationAxis, double);
  vtkSetVector3Macro(RotationCenter, double);
  vtkGetVector3Macro(RotationCenter, double);
  vtkSetClampMacro(RotationAnglePerStep, double, -360, 360);
  vtkGetMacro(RotationAnglePerStep, double);
  ///@}

  ///@{
  /// Steps after the input: the time steps are 0..NumberOfSteps. Default 10.
  vtkSetClampMacro(NumberOfSteps, int, 0, 1000000);
  vtkGetMacro(NumberOfSteps, int);
  ///@}

  ///@{
  /// delta_dist of thesis 3.4.3, in grid cells. Default 3.
  vtkSetClampMacro(DistanceThreshold, double, 1, 100);
  vtkGetMacro(DistanceThreshold, double);
  ///@}

  ///@{
  /// Cell edge of the grids (model units); 0 (default): automatic.
  vtkSetClampMacro(GridCellSize, double, 0, 1e30);
  vtkGetMacro(GridCellSize, double);
  ///@}

  ///@{
  /// Quality improvement of the deformed region (3.6). Default on.
  vtkSetMacro(Improve, vtkTypeBool);
  vtkGetMacro(Improve, vtkTypeBool);
  vtkBooleanMacro(Improve, vtkTypeBool);
  ///@}

  ///@{
  /// Improve's quality floor (stretch); 0: the input's minimum stretch,
  /// within [0.1, 0.4]. Default 0.3.
  vtkSetClampMacro(QualityFloor, double, 0, 0.6);
  vtkGetMacro(QualityFloor, double);
  ///@}

  ///@{
  /// Bound of the cached steps, in MB. Default 1024.
  vtkSetClampMacro(CacheMemoryLimit, int, 0, VTK_INT_MAX);
  vtkGetMacro(CacheMemoryLimit, int);
  ///@}

  /// Steps computed (AdaptSession::advance calls that succeeded) since the
  /// filter was made: a request served from the cache adds none.
  vtkGetMacro(ComputedSteps, vtkIdType);
  /// Steps whose session copy the cache holds now (step 0 included).
  int GetNumberOfCachedSteps() const;

  /// The mesh of the requested step and the table of steps.
  vtkUnstructuredGrid* GetMeshOutput();
  vtkTable* GetStepsOutput();

protected:
  vtkFEMorphAdapt();
  ~vtkFEMorphAdapt() override;

  /// Gathered on process 0: the deformation and remeshing work on the whole mesh.
  PieceMode GetPieceMode() const override { return Gathered; }

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  std::string GetInputName(int port) override;

  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  std::string MaterialArray = "MaterialId";
  int MovingObject = 1;
  double TranslationPerStep[3] = { 0, 0, 0 };
  double RotationAxis[3] = { 1, 0, 0 };
  double RotationCenter[3] = { 0, 0, 0 };
  double RotationAnglePerStep = 0;
  int NumberOfSteps = 10;
  double DistanceThreshold = 3;
  double GridCellSize = 0;
  vtkTypeBool Improve = 1;
  double QualityFloor = 0;
  int CacheMemoryLimit = 1024;

private:
  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
  vtkIdType ComputedSteps = 0;
  /// The output port whose request is being served (its UPDATE_TIME_STEP
  /// is the step to produce).
  int RequestedPort = 0;

  vtkFEMorphAdapt(const vtkFEMorphAdapt&) = delete;
  void operator=(const vtkFEMorphAdapt&) = delete;
};

#endif
