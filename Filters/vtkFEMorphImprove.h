/**
 * @class   vtkFEMorphImprove
 * @brief   improves the elements of a tetrahedral mesh without changing the
 *          part's shape, density or geometric accuracy (Phased ODT)
 *
 * ParaView: "FEMorph Improve" (menu FEMorph). Thesis 2.6 (Fig. 2.34): after
 * a dimension change or a motion step, stretched, flat (sliver, cap, spade)
 * and inverted tetrahedra are repaired and the original mesh density and
 * shape approximation accuracy are recovered. The modified ODT loop --
 * degenerated and inverted element removal (2.6.2), mesh density control
 * (2.6.3), shape approximation accuracy control (2.6.4), ODT smoothing
 * (2.6.5) -- runs on the boundary curves, the surface triangles and the
 * tetrahedra in that order; boundary vertices stay on the fitted surfaces
 * and curves of the segmentation, and the surface vertices of a region no
 * surface fits on that region's input triangles (MoveUnfittedRegions). The
 * algorithm is femorph_core's
 * phased_odt() (Core/improve/phased_odt.h).
 *
 * Input 0 (`Input`): the mesh to improve, VTK_TETRA cells only, with the
 * segmentation arrays FEMorph Segment writes (FaceRegion, VertexClass,
 * RegionType, RegionParameters, curves). Without them the filter says so and
 * segments the mesh itself (SegmentIfMissing, default) or keeps every
 * boundary vertex where it is; a mesh that carries some of them must carry
 * all, valid (an error names the array and what is wrong: a region id that
 * names no region, a short array, a NaN fit parameter...). Inverted
 * tetrahedra are accepted (they are what Improve repairs) when they are
 * oriented consistently with their neighbours; non-tetrahedral cells, NaN
 * coordinates, a non-conforming or non-manifold mesh are errors. An input
 * without cells gives an empty output and a warning. The input is never
 * modified.
 *
 * Input 1 (`Reference`, optional): the mesh before the deformation. With the
 * input's connectivity (same points and cells), its vertex densities
 * (Eq. 2.32) travel with the material onto the input (Eq. 2.33); otherwise
 * its density field is taken in space. When it carries segmentation arrays
 * its largest geometric error per region is the acceptable error (2.6.4).
 * Without a reference the input's own density and geometric error are kept.
 *
 * Output: the improved mesh. Point data interpolated onto new points, cell
 * data copied from the cell each new cell comes from, FaceRegion and
 * VertexClass rewritten, the segmentation's field data kept (CurveVertices
 * and CurveOffsets renumbered to the output's points). Cell data `Stretch`
 * (Eq. 1.1) and `Inverted` (unsigned char, 1 for a tetrahedron with negative
 * volume that could not be repaired; only with RequireValid off). Field data,
 * one tuple each: `ImproveStretch` (min and mean, before and after),
 * `ImproveDensityError` (mean density error Eq. 2.35 before and after, over
 * the RegionArrayName cells when set; NaN without density control), `ImproveCounts` (splits, collapses, accuracy
 * splits, flips 2-3, 3-2, 4-4, surface flips, removed slivers, caps, spades,
 * repaired inverted tetrahedra, remaining inverted, moved vertices,
 * BelowFloor: tetrahedra left below QualityFloor, BelowFloorAllBoundary:
 * those of them with all four vertices on the boundary -- their shape is
 * that of the boundary triangles, e.g. across a face much narrower than the
 * mesh, and a warning says so --, tets before and after, LeftAsItWas: 1 when
 * the mesh needed nothing -- no inverted tetrahedron, every stretch at
 * QualityFloor or more, no edge beyond the density thresholds, every curved
 * region within its acceptable error --
 * and is output unchanged, KeptInput: 1 when the result's minimum stretch
 * fell below min(the input's minimum, QualityFloor) -- without a Reference,
 * below the input's minimum -- and the input is output unchanged instead,
 * with a warning), `ImproveTimes` (seconds: segmentation, curves,
 * surfaces, volume, total), `ImproveStepTimes` (the same time by step:
 * preparation, degenerate and inverted removal, density control, accuracy
 * control, smoothing, flips, finishing, output); with TraceQuality,
 * `ImproveQualityTrace` (seconds and minimum stretch, one tuple per step);
 * one tuple per region: `GeometricError` (largest
 * distance of a boundary edge's midpoint to the region's fitted curved
 * surface, after) and `AcceptableGeometricError` (the target; NaN for planes
 * and unknown regions).
 *
 * @sa vtkFEMorphSegment, vtkFEMorphMeshQuality
 */
#ifndef vtkFEMorphImprove_h
#define vtkFEMorphImprove_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

#include <string>

class FEMORPHFILTERS_EXPORT vtkFEMorphImprove : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphImprove* New();
  vtkTypeMacro(vtkFEMorphImprove, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The reference mesh (before the deformation), input port 1. Optional.
  void SetReferenceData(vtkDataObject* reference) { this->SetInputData(1, reference); }
  void SetReferenceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  ///@{
  /**
   * Beyond the thesis: repair only the poor tetrahedra (stretch below
   * QualityFloor, inverted, degenerated) and leave the rest of the mesh as it is, as Gmsh's
   * and TetGen's optimizers do: flat and inverted tetrahedra removed, the
   * vertices of the poor ones smoothed (curves, surfaces, volume, with
   * flips), then their inner vertices placed for the best worst tet and
   * their interior edges split where that is not enough. No density or
   * accuracy control and no sweep over the whole mesh, so the Reference is
   * not used for a density target (ImproveDensityError is NaN). Much faster
   * than the phased loop, but a stretched region keeps its stretched
   * elements and a lower minimum (figures: Testing/Benchmarks/RESULTS.md).
   * Its time is reported under the steps Removal, Smoothing and Finishing.
   * Default off.
   */
  vtkSetMacro(PoorElementsOnly, vtkTypeBool);
  vtkGetMacro(PoorElementsOnly, vtkTypeBool);
  vtkBooleanMacro(PoorElementsOnly, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Phases of Phased ODT smoothing (thesis 2.6.5): boundary curves (CPT
   * smoothing on lines, central angles on circles), surface triangles (2D
   * ODT in each region's parameter plane, surface edge flips) and
   * tetrahedra (3D ODT, flips 2-3, 3-2, 4-4). Default all on.
   */
  vtkSetMacro(SmoothCurves, vtkTypeBool);
  vtkGetMacro(SmoothCurves, vtkTypeBool);
  vtkBooleanMacro(SmoothCurves, vtkTypeBool);
  vtkSetMacro(SmoothSurfaces, vtkTypeBool);
  vtkGetMacro(SmoothSurfaces, vtkTypeBool);
  vtkBooleanMacro(SmoothSurfaces, vtkTypeBool);
  vtkSetMacro(SmoothVolume, vtkTypeBool);
  vtkGetMacro(SmoothVolume, vtkTypeBool);
  vtkBooleanMacro(SmoothVolume, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Steps of the modified ODT loop: removal of flat tetrahedra (slivers,
   * caps, spades; 2.6.2), repair of inverted tetrahedra (half-edge
   * collapses, 2.6.2), mesh density control (split and collapse, 2.6.3),
   * shape approximation accuracy control (2.6.4), flips. Default all on.
   */
  vtkSetMacro(RemoveDegenerate, vtkTypeBool);
  vtkGetMacro(RemoveDegenerate, vtkTypeBool);
  vtkBooleanMacro(RemoveDegenerate, vtkTypeBool);
  vtkSetMacro(RemoveInverted, vtkTypeBool);
  vtkGetMacro(RemoveInverted, vtkTypeBool);
  vtkBooleanMacro(RemoveInverted, vtkTypeBool);
  vtkSetMacro(DensityControl, vtkTypeBool);
  vtkGetMacro(DensityControl, vtkTypeBool);
  vtkBooleanMacro(DensityControl, vtkTypeBool);
  vtkSetMacro(AccuracyControl, vtkTypeBool);
  vtkGetMacro(AccuracyControl, vtkTypeBool);
  vtkBooleanMacro(AccuracyControl, vtkTypeBool);
  vtkSetMacro(Flips, vtkTypeBool);
  vtkGetMacro(Flips, vtkTypeBool);
  vtkBooleanMacro(Flips, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Beyond the thesis: with a density target, the finishing round smooths the
   * inner vertices with one ODT sweep, then moves the surface vertices along
   * their fitted surfaces for OdtIterations sweeps and the inner vertices for
   * one sweep more, each toward where its edges have the target length
   * 1 / rho_GC (springs; no tet inverts and no ball's worst tet falls below
   * min(its stretch, 0.35) or loses more than 10%; surface vertices stay on
   * their surface and within the acceptable geometric error). It lowers the
   * density error (Eq. 2.35) at some extra time. Default on.
   */
  vtkSetMacro(RelaxEdgeLengths, vtkTypeBool);
  vtkGetMacro(RelaxEdgeLengths, vtkTypeBool);
  vtkBooleanMacro(RelaxEdgeLengths, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Let the surface vertices of a region the segmentation could not fit (a
   * stretched fillet, a free-form face; RegionType unknown) move on that
   * region's triangles as they are in the input, instead of staying where
   * they are. Beyond the thesis. Default on.
   */
  vtkSetMacro(MoveUnfittedRegions, vtkTypeBool);
  vtkGetMacro(MoveUnfittedRegions, vtkTypeBool);
  vtkBooleanMacro(MoveUnfittedRegions, vtkTypeBool);
  ///@}

  ///@{
  /**
   * ODT sweeps per step of the loop (thesis: two or three). In [1, 100].
   * Default 2. With RelaxEdgeLengths on, the finishing round makes one ODT
   * sweep and then this many edge-length relaxation sweeps of the surface
   * vertices and one more of the inner vertices.
   */
  vtkSetClampMacro(OdtIterations, int, 1, 100);
  vtkGetMacro(OdtIterations, int);
  ///@}

  ///@{
  /**
   * Repetitions of the modified ODT loop per phase at most (the loop stops
   * earlier when no density or accuracy operation is left). In [1, 1000].
   * Default 8.
   */
  vtkSetClampMacro(MaxLoops, int, 1, 1000);
  vtkGetMacro(MaxLoops, int);
  ///@}

  ///@{
  /**
   * Density thresholds (2.6.3): an edge is split when its length times the
   * target density reaches SplitThreshold (beta1, default 1.5) and collapsed
   * when it is at most CollapseThreshold (beta2, default 0.67). The loop
   * converges when beta1 > 2 beta2 and 1 + beta2 / 2 < beta1; other values
   * are an error. SplitThreshold in [1, 100], CollapseThreshold in [0, 1].
   * Beyond the thesis, a long edge is split at its midpoint and its halves
   * again while long, but at a third when its length times the density is
   * in [2.5, 3.5), where three pieces are nearer the target than two or four.
   */
  vtkSetClampMacro(SplitThreshold, double, 1.0, 100.0);
  vtkGetMacro(SplitThreshold, double);
  vtkSetClampMacro(CollapseThreshold, double, 0.0, 1.0);
  vtkGetMacro(CollapseThreshold, double);
  ///@}

  ///@{
  /**
   * Edge of the cells of the regular grid holding the target density field
   * (Eq. 2.33), in model units. 0 (default): half the mean edge length of
   * the reference (or input) mesh, as the thesis suggests. In [0, 1e30].
   */
  vtkSetClampMacro(GridCellSize, double, 0.0, 1e30);
  vtkGetMacro(GridCellSize, double);
  ///@}

  ///@{
  /**
   * gamma_st (2.6.2): tetrahedra with a stretch (Eq. 1.1) below it are
   * degenerated and removed; no operation may create one. In [0, 0.5].
   * Default 0.05.
   */
  vtkSetClampMacro(DegenerateThreshold, double, 0.0, 0.5);
  vtkGetMacro(DegenerateThreshold, double);
  ///@}

  ///@{
  /**
   * The stretch (Eq. 1.1) a tetrahedron should reach (beyond the thesis):
   * the finishing passes, and Poor Elements Only throughout, repair the
   * tetrahedra below it (vertex placement, splits, flips), and no boundary
   * step may make a tetrahedron below it that is worse than the worst one it
   * replaces. A lower floor leaves more of the mesh as it is and takes less
   * time. Above DegenerateThreshold, in [0.05, 0.6]. Default 0.3 (also the default of
   * Gmsh's optimizer threshold, in its own measure).
   */
  vtkSetClampMacro(QualityFloor, double, 0.05, 0.6);
  vtkGetMacro(QualityFloor, double);
  ///@}

  ///@{
  /**
   * Name of a cell array (any numeric type) restricting the improvement to
   * the cells where it is nonzero, e.g. the cells Deform or Adapt moved.
   * Only vertices all of whose cells are flagged move or change. Empty
   * (default): the whole mesh. The array must be numeric, with one
   * component and one finite value per cell; anything else (no such array,
   * a string array, a short array, a NaN) is an error naming it.
   */
  vtkSetStdStringFromCharMacro(RegionArrayName);
  vtkGetCharFromStdStringMacro(RegionArrayName);
  ///@}

  ///@{
  /**
   * When the input has no segmentation arrays: segment it with FEMorph
   * Segment's defaults (on, default) or keep every boundary vertex fixed.
   */
  vtkSetMacro(SegmentIfMissing, vtkTypeBool);
  vtkGetMacro(SegmentIfMissing, vtkTypeBool);
  vtkBooleanMacro(SegmentIfMissing, vtkTypeBool);
  ///@}

  ///@{
  /**
   * When inverted or zero-volume tetrahedra remain that no local operation
   * could repair (a tangled or flat input): fail with an error naming how
   * many and where (on, default), or output the mesh with them (inverted
   * ones marked in the `Inverted` cell array, flat ones with Stretch 0) and
   * a warning.
   */
  vtkSetMacro(RequireValid, vtkTypeBool);
  vtkGetMacro(RequireValid, vtkTypeBool);
  vtkBooleanMacro(RequireValid, vtkTypeBool);
  ///@}

  ///@{
  /**
   * For benchmarks: record the minimum stretch after every step of the
   * loop in the field array `ImproveQualityTrace` (components Seconds, since
   * the filter started, and MinStretch; one tuple per step), so the time
   * the improvement took to reach a given minimum can be read off. One pass
   * over the tetrahedra per step, left out of the recorded times. Default
   * off.
   */
  vtkSetMacro(TraceQuality, vtkTypeBool);
  vtkGetMacro(TraceQuality, vtkTypeBool);
  vtkBooleanMacro(TraceQuality, vtkTypeBool);
  ///@}

protected:
  vtkFEMorphImprove();
  ~vtkFEMorphImprove() override;

  /// Gathered on process 0: remeshing a piece alone would crack the mesh along the cut.
  PieceMode GetPieceMode() const override { return Gathered; }

  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  std::string GetInputName(int port) override;

  // Defaults: femorph::PhasedOdtOptions and ImproveTargetOptions (set in
  // the constructor).
  vtkTypeBool PoorElementsOnly;
  vtkTypeBool SmoothCurves;
  vtkTypeBool SmoothSurfaces;
  vtkTypeBool SmoothVolume;
  vtkTypeBool RemoveDegenerate;
  vtkTypeBool RemoveInverted;
  vtkTypeBool DensityControl;
  vtkTypeBool AccuracyControl;
  vtkTypeBool Flips;
  vtkTypeBool RelaxEdgeLengths;
  vtkTypeBool MoveUnfittedRegions;
  int OdtIterations;
  int MaxLoops;
  double SplitThreshold;
  double CollapseThreshold;
  double GridCellSize;
  double DegenerateThreshold;
  double QualityFloor;
  vtkTypeBool TraceQuality;
  std::string RegionArrayName;
  vtkTypeBool SegmentIfMissing = 1;
  vtkTypeBool RequireValid = 1;

private:
  vtkFEMorphImprove(const vtkFEMorphImprove&) = delete;
  void operator=(const vtkFEMorphImprove&) = delete;
};

#endif
