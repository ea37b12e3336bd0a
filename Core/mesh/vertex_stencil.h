// Combination of vertex stencils, so point data can follow new vertices.
#pragma once

#include "mesh/tet_mesh.h"

namespace femorph {

/// Stencil of sum_k weight[k] * stencil[k] over n <= 4 stencils (weights summing to
/// one), truncated to the four input vertices with the largest weights and
/// renormalised.
VertexStencil combine_stencils(const VertexStencil* const* stencils, const double* weights, int n);

}  // namespace femorph
