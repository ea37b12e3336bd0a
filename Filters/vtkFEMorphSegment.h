/**
 * @class   vtkFEMorphSegment
 * @brief   recognises the CAD surfaces of a tetrahedral mesh: planes,
 *          cylinders, cones, spheres and tori, and the curves between them
 *
 * ParaView: "FEMorph Segment" (menu FEMorph). Thesis 2.4 (A11-A16): sharp
 * edges, curvature by the normal tensor, region extraction by seeds and
 * growing (planes, cylinders, cones, spheres, tori), Levenberg-Marquardt
 * refinement of the fits, boundary curves. The algorithm is femorph_core's
 * segment_surface() (Core/segment/segmentation.h) on the boundary surface of
 * the mesh; this class converts, reports progress and writes the arrays.
 *
 * Input: a vtkUnstructuredGrid of VTK_TETRA cells only (other cell types are
 * an error naming each type and its count; ParaView's Tetrahedralize converts
 * them). The tets must be consistently oriented (either vertex order), with a
 * manifold boundary; the core's message (e.g. a non-manifold boundary edge)
 * is reported otherwise. Zero-volume tets are accepted with a warning (only
 * the boundary surface is segmented; its degenerate triangles are counted;
 * FEMorph Improve repairs such a mesh, FEMorph Deform refuses it).
 * Boundary points on top of other boundary points (an unmerged seam of
 * duplicate nodes, which the segmentation would take for faces inside the
 * part) are counted in a warning that says to merge them first (Clean to
 * Grid, vtkStaticCleanUnstructuredGrid).
 *
 * Output 0 ("Mesh"): a shallow copy of the input (the input is never
 * modified) with the arrays of docs/ARCHITECTURE.md, written by
 * vtkFEMorphSegmentationArrays (the input's own segmentation arrays, if
 * any, are not read: they are replaced):
 * - cell data `FaceRegion` (int, 4 components: region of the face opposite
 *   local vertex i, -1 interior), point data `VertexClass` (unsigned char:
 *   0 inner, 1 surface, 2 curve, 3 corner);
 * - field data per region: `RegionType` (0 plane, 1 cylinder, 2 cone,
 *   3 sphere, 4 torus, 5 unknown), `RegionParameters` (12 doubles, layout in
 *   Core/segment/segmentation.h), `RegionConvexity` (0 n/a, 1 convex,
 *   2 concave); per curve: `CurveType`, `CurveParameters` (20 doubles),
 *   `CurveClosed`, and `CurveVertices` with `CurveOffsets` (the ordered point
 *   ids of each curve); `SegmentationTimes` (seconds per step).
 *
 * Output 1 ("Surface"): the boundary surface as vtkPolyData: triangles with
 * cell data `RegionId` and `RegionType`, the boundary curves as
 * VTK_POLY_LINE cells (a closed loop repeats its first point) with `CurveId`
 * and `CurveType`; each kind has -1 in the other's arrays. vtkPolyData puts
 * the lines first. Point data: `MeshPointId` (the point of output 0),
 * `VertexClass` and the input's point data.
 *
 * Output 2 ("Regions"): a vtkTable, one row per region, as a CAD feature
 * list: RegionId, TypeName, Radius, MajorRadius, MinorRadius, HalfAngle
 * (degrees), Axis, Center, Apex, Normal, Point (3 components each), Area,
 * Convexity ("convex", "concave" or ""), TriangleCount, FitResidual (RMS
 * distance to the fit), Neighbors (e.g. "2 5 7"); NaN where a column does
 * not apply to the region's type.
 *
 * An input without cells gives empty outputs and a warning. An abort leaves
 * the outputs empty. The segmentation's warnings (regions left unknown, fits
 * that did not converge) are reported with vtkWarningMacro.
 *
 * @warning Each piece is segmented on its own: in a distributed run the
 * partition boundaries would become surfaces. Run it on one process (or
 * after Merge Blocks / a redistribution to one rank).
 *
 * @sa vtkFEMorphSegmentationArrays (the arrays, and the reader Deform and
 * Improve use), vtkFEMorphMeshQuality
 */
#ifndef vtkFEMorphSegment_h
#define vtkFEMorphSegment_h

#include "FEMorphFiltersModule.h" // For export macro
#include "vtkFEMorphAlgorithm.h"

class vtkPolyData;
class vtkTable;

class FEMORPHFILTERS_EXPORT vtkFEMorphSegment : public vtkFEMorphAlgorithm
{
public:
  static vtkFEMorphSegment* New();
  vtkTypeMacro(vtkFEMorphSegment, vtkFEMorphAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * A11: an edge of the boundary surface is sharp when the normals of its two
   * triangles differ by more than this angle; regions do not grow across
   * sharp edges. Degrees, in [0, 180]. Default 30.
   */
  vtkSetClampMacro(SharpAngle, double, 0.0, 180.0);
  vtkGetMacro(SharpAngle, double);
  ///@}

  ///@{
  /**
   * A13 cylinder seeds: neighbouring minimum-curvature directions agree
   * within this angle on a cylinder (thesis 2.4.3.2: 1.0 to 1.5). Degrees,
   * in [0, 90]. Default 1.5.
   */
  vtkSetClampMacro(CylinderAngleTolerance, double, 0.0, 90.0);
  vtkGetMacro(CylinderAngleTolerance, double);
  ///@}

  ///@{
  /**
   * A13 cone seeds: the same on a cone (thesis: 0.4 to 0.8). Degrees, in
   * [0, 90]. Default 0.8.
   */
  vtkSetClampMacro(ConeAngleTolerance, double, 0.0, 90.0);
  vtkGetMacro(ConeAngleTolerance, double);
  ///@}

  ///@{
  /**
   * A13 sphere seeds: a triangle whose vertices' principal directions differ
   * by more than this angle is a sphere seed (thesis: 60). Degrees, in
   * [0, 90]. Default 60.
   */
  vtkSetClampMacro(SphereDirectionAngle, double, 0.0, 90.0);
  vtkGetMacro(SphereDirectionAngle, double);
  ///@}

  ///@{
  /**
   * The distance tolerance of vertices inside a face: such a vertex lies on
   * a fitted surface when closer than this times the mean edge length of the
   * boundary surface. It is the largest tolerance used: Adaptive Tolerance
   * may lower it, never raise it. Vertices on a face's boundary curves get
   * their own tolerance, measured on the mesh (never below this one).
   * Relative, in (0, 1]. Default 0.01.
   */
  vtkSetClampMacro(DistanceTolerance, double, 0.0, 1.0);
  vtkGetMacro(DistanceTolerance, double);
  ///@}

  ///@{
  /**
   * RANSAC iterations of the cone, sphere and torus fits. In [1, 1000000].
   * Default 500.
   */
  vtkSetClampMacro(RansacIterations, int, 1, 1000000);
  vtkGetMacro(RansacIterations, int);
  ///@}

  ///@{
  /**
   * Lower the Distance Tolerance to the mesh's own precision: 1e4 times the
   * median distance of the nodes of its planar faces to their planes (at
   * least 1e-6 of the part size), when that is smaller. Keeps region
   * boundaries where faces meet at a fraction of a degree on meshes whose
   * nodes lie on the CAD surfaces. Off: the Distance Tolerance as given.
   * Either way, nodes on boundary curves (which CAD files store as
   * approximations) are tested with the curve tolerance, 6 times the
   * 0.9-quantile of the planar faces' border node distances, at most 1e-3
   * of the part. Default on.
   */
  vtkSetMacro(AdaptiveTolerance, vtkTypeBool);
  vtkGetMacro(AdaptiveTolerance, vtkTypeBool);
  vtkBooleanMacro(AdaptiveTolerance, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Seed of RANSAC's random numbers: the same seed gives the same result.
   * In [0, VTK_INT_MAX]. Default 1.
   */
  vtkSetClampMacro(RandomSeed, int, 0, VTK_INT_MAX);
  vtkGetMacro(RandomSeed, int);
  ///@}

  ///@{
  /**
   * A15: refine every curved region's fit by Levenberg-Marquardt. Default on.
   */
  vtkSetMacro(RefineFits, vtkTypeBool);
  vtkGetMacro(RefineFits, vtkTypeBool);
  vtkBooleanMacro(RefineFits, vtkTypeBool);
  ///@}

  ///@{
  /// The outputs by port: 0 the mesh, 1 the boundary surface, 2 the regions.
  vtkUnstructuredGrid* GetMeshOutput();
  vtkPolyData* GetSurfaceOutput();
  vtkTable* GetRegionTableOutput();
  ///@}

protected:
  vtkFEMorphSegment();
  ~vtkFEMorphSegment() override;

  /// Gathered on process 0: regions span the pieces.
  PieceMode GetPieceMode() const override { return Gathered; }

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  bool CheckProperties() override;
  bool Execute(vtkUnstructuredGrid* input, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  // Defaults: femorph::SegmentationParams (set in the constructor).
  double SharpAngle;
  double CylinderAngleTolerance;
  double ConeAngleTolerance;
  double SphereDirectionAngle;
  double DistanceTolerance;
  vtkTypeBool AdaptiveTolerance;
  int RansacIterations;
  int RandomSeed;
  vtkTypeBool RefineFits;

private:
  vtkFEMorphSegment(const vtkFEMorphSegment&) = delete;
  void operator=(const vtkFEMorphSegment&) = delete;
};

#endif
