// Principal curvatures and directions by the normal tensor framework, thesis
// 2.4.2 (A12), Eqs. 2.1-2.5, per vertex and per triangle.
#pragma once

#include "mesh/surface_mesh.h"
#include "segment/detect_sharp_edges.h"

#include <vector>

namespace femorph {

struct Curvature {
  // Per vertex. Vertices on sharp edges are not evaluated (valid = 0): their
  // normal tensor mixes two surfaces (thesis 2.4.2).
  std::vector<char> vertex_valid;
  // "Maximum" and "minimum" are by magnitude, as the thesis uses them: on a
  // cylinder k_max = +-1/R around it and k_min = 0 along the generatrix
  // (dir_min is the axis direction). Signs: > 0 where the surface bends away
  // from its outward normal (convex: a boss, a ball), < 0 concave (a hole).
  /// Unit outward normal: e1 of the normal tensor, refined by a height fit
  /// (see the .cpp); on vertices not evaluated, the area-weighted mean of the
  /// triangle normals around it.
  std::vector<Vec3> vertex_normal;
  std::vector<double> vertex_k_max;    // |k_max| >= |k_min|
  std::vector<double> vertex_k_min;
  std::vector<Vec3> vertex_dir_max;    // unit principal direction of k_max
  std::vector<Vec3> vertex_dir_min;    // unit principal direction of k_min
  // Per triangle: the average over its valid vertices (thesis: of its three
  // vertices). Directions are sign-aligned before averaging. valid = 0 when
  // none of its vertices is.
  std::vector<char> triangle_valid;
  std::vector<double> triangle_k_max, triangle_k_min;
  std::vector<Vec3> triangle_dir_max, triangle_dir_min;
};

/// Eq. 2.1: N_i = sum over the triangles t around i of n_t n_t^T; its
/// eigenvectors e1 (normal), e2, e3 (principal directions). Eqs. 2.2-2.3: the
/// 2x2 shape operator from the gradient of the vertex normal over the 1-ring,
/// with the fallback of Eqs. 2.4-2.5 when A_Gr A_Gr^T is singular.
/// Parallel over vertices.
Curvature normal_tensor_curvature(const SurfaceMesh& surface, const SharpEdges& sharp);

/// Eq. 2.6: variance of unit vectors v over a neighbourhood: mean of
/// |v_eta - v_bar|^2 with v_bar the normalised sum. Vectors may be given with
/// either sign (principal directions): `unsigned_directions` aligns them with
/// the first one before summing.
double vector_variance(const Vec3* vectors, int count, bool unsigned_directions);

}  // namespace femorph
