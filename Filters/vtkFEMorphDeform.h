/**
 * @class   vtkFEMorphDeform
 * @brief   changes one dimension of a tetrahedral mesh like a CAD system
 *          (a distance, a radius, a fillet, a chamfer, a position) by moving
 *          its vertices, locally, and improves the result
 *
 * ParaView: "FEMorph Deform" (menu FEMorph). Thesis 2.5: the regions of the
 * segmentation are classified into control (the region whose dimension
 * changes), following (its fillets and chamfers, which move with it),
 * deformed (their neighbours, which stretch) and fixed regions; the control
 * and following regions are rebuilt for the target value (Table 2.7) and
 * their vertices mapped onto them; curve and surface vertices of the
 * deformed regions follow by their division ratios and 2D mean value
 * coordinates, then onto their surfaces; inner vertices by 3D mean value
 * coordinates (one sparse system, Eq. 2.10). Only the deformable region near
 * the moved regions changes (LocalRegion). FEMorph Improve's core then runs
 * on that region with the undeformed mesh as reference (Improve), so the
 * output keeps the input's density and chord accuracy; a change that would
 * invert tetrahedra is taken in smaller steps with improvement in between.
 * The algorithm is femorph_core's deform_mesh() (Core/deform/deform.h).
 *
 * Input: VTK_TETRA cells with FEMorph Segment's arrays (output 0 of
 * Segment); without them the mesh is segmented with Segment's default
 * settings and a warning says so. The input is never modified.
 *
 * Properties:
 * - DeformationType: 0 Distance (between the control plane and the
 *   parallel reference plane: a boss height, a hole depth, a width),
 *   1 CylinderRadius (a boss or hole radius; coaxial fillets and chamfers
 *   follow), 2 FilletRadius (a cylindrical or toroidal fillet's radius; its
 *   equal-radius sphere corners and the fillets meeting there follow),
 *   3 ChamferAngle (degrees between the chamfer and the reference face, the
 *   leg on the reference face kept), 4 ChamferLength (the leg on the
 *   reference face, measured from the edge the chamfer replaced; the angle
 *   kept), 5 SphereRadius (centre kept), 6 Position (the object moved by
 *   Translation on its reference plane(s)).
 * - ControlRegion: the region id (Segment's Regions table lists them); -1
 *   (default) with UseControlPoint: the region whose boundary passes nearest
 *   to ControlPoint.
 * - ReferenceRegions: Distance: the opposite plane; chamfers: the face the
 *   angle and length are measured on; Position: the plane(s) the object
 *   sits on. Empty: chosen automatically (the nearest parallel plane, the
 *   chamfer's largest planar neighbour, the large planes around the object)
 *   and reported in field data `ReferenceRegions`.
 * - TargetValue: the new dimension (mesh units, or degrees for
 *   ChamferAngle). 0 (default): measure only: the output is the input with
 *   `RegionRole` and `Deformable` marked and `CurrentDimension` and
 *   `ValidRange` in field data. Position: the distance to move along
 *   Translation (0: |Translation|; a zero Translation: measure only). NaN
 *   or infinite: an error.
 * - Translation: Position's displacement (world coordinates, parallel to
 *   the reference plane).
 * - FollowingRegions: replaces the automatic following regions (-1 alone:
 *   none).
 * - LocalRegion (on): reposition and improve only the deformable region.
 * - Improve (on): Phased ODT on the deformable region after each step.
 *   Off: the filter keeps its parameterisation (the deformable region,
 *   the mean value coordinates and the factorised systems) between runs,
 *   so that a new TargetValue (dragged in ParaView, a sweep in pvpython)
 *   costs only the repositioning; a change that would invert tetrahedra is
 *   then an error.
 * - MaxStepFraction (1): largest fraction of the change per step; steps are
 *   halved further while one would invert tetrahedra (up to MaxSteps).
 * - QualityFloor (0.3): Improve's floor.
 *
 * Output: the deformed mesh, point and cell data of the input carried
 * (interpolated onto new points), the segmentation arrays updated
 * (RegionParameters with the new surfaces; curves traced and refitted),
 * point data `Displacement`, cell data `RegionRole` (int, 4 components, per
 * face: 0 fixed, 1 control, 2 following, 3 deformed, -1 interior),
 * `Deformable` (unsigned char) and `Stretch`; field data `CurrentDimension`,
 * `TargetDimension`, `ValidRange` (Min, Max), `DeformSteps`,
 * `ReferenceRegions`, `RegionRoles` (per region), `DeformCounts`,
 * `DeformStretch` and `DeformTimes`.
 *
 * Errors (empty output): a control region of the wrong type for the
 * deformation type, a target outside the valid range (the message gives
 * it), no parallel reference plane, a Position translation out of the
 * plane, a change that would leave tetrahedra inverted.
 *
 * @sa vtkFEMorphSegment, vtkFEMorphImprove
 */
#ifndef vtkFEMorphDeform_h
#define vtkFEMorphDeform_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

#include <memory> // For std::shared_ptr
#include <string> // For std::string
#include <vector> // For std::vector

namespace femorph
{
class DeformSession;
}

class FEMORPHFILTERS_EXPORT vtkFEMorphDeform : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphDeform* New();
  vtkTypeMacro(vtkFEMorphDeform, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum DeformationTypes
  {
    Distance = 0,
    CylinderRadius = 1,
    FilletRadius = 2,
    ChamferAngle = 3,
    ChamferLength = 4,
    SphereRadius = 5,
    Position = 6
  };

  vtkSetClampMacro(DeformationType, int, 0, 6);
  vtkGetMacro(DeformationType, int);

  vtkSetMacro(ControlRegion, int);
  vtkGetMacro(ControlRegion, int);
  vtkSetVector3Macro(ControlPoint, double);
  vtkGetVector3Macro(ControlPoint, double);
  vtkSetMacro(UseControlPoint, vtkTypeBool);
  vtkGetMacro(UseControlPoint, vtkTypeBool);
  vtkBooleanMacro(UseControlPoint, vtkTypeBool);

  ///@{
  /// ReferenceRegions and FollowingRegions (ids).
  void AddReferenceRegion(int id);
  void RemoveAllReferenceRegions();
  int GetNumberOfReferenceRegions() const { return static_cast<int>(this->ReferenceRegions.size()); }
  int GetReferenceRegion(int i) const;
  void AddFollowingRegion(int id);
  void RemoveAllFollowingRegions();
  int GetNumberOfFollowingRegions() const { return static_cast<int>(this->FollowingRegions.size()); }
  int GetFollowingRegion(int i) const;
  ///@}

  vtkSetMacro(TargetValue, double);
  vtkGetMacro(TargetValue, double);
  vtkSetVector3Macro(Translation, double);
  vtkGetVector3Macro(Translation, double);

  vtkSetMacro(LocalRegion, vtkTypeBool);
  vtkGetMacro(LocalRegion, vtkTypeBool);
  vtkBooleanMacro(LocalRegion, vtkTypeBool);
  vtkSetMacro(Improve, vtkTypeBool);
  vtkGetMacro(Improve, vtkTypeBool);
  vtkBooleanMacro(Improve, vtkTypeBool);
  vtkSetClampMacro(MaxStepFraction, double, 0.001, 1.0);
  vtkGetMacro(MaxStepFraction, double);
  vtkSetClampMacro(MaxSteps, int, 1, 1024);
  vtkGetMacro(MaxSteps, int);
  vtkSetClampMacro(QualityFloor, double, 0.05, 0.6);
  vtkGetMacro(QualityFloor, double);

protected:
  vtkFEMorphDeform();
  ~vtkFEMorphDeform() override;

  /// Gathered on process 0: the deformable region and its solve span the whole mesh.
  PieceMode GetPieceMode() const override { return Gathered; }

  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  int DeformationType = Distance;
  int ControlRegion = -1;
  double ControlPoint[3] = { 0, 0, 0 };
  vtkTypeBool UseControlPoint = 0;
  std::vector<int> ReferenceRegions;
  std::vector<int> FollowingRegions;
  double TargetValue = 0;
  double Translation[3] = { 0, 0, 0 };
  vtkTypeBool LocalRegion = 1;
  vtkTypeBool Improve = 1;
  double MaxStepFraction = 1.0;
  int MaxSteps = 32;
  double QualityFloor = 0.3;

private:
  /// Without Improve: the parameterisation of the last run, reused while
  /// only TargetValue changes (2.5.4: parameterise once, reposition many).
  std::shared_ptr<femorph::DeformSession> Session;
  std::string SessionKey;

  vtkFEMorphDeform(const vtkFEMorphDeform&) = delete;
  void operator=(const vtkFEMorphDeform&) = delete;
};

#endif
