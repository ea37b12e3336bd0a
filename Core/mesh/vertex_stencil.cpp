#include "mesh/vertex_stencil.h"

#include <algorithm>

namespace femorph {

VertexStencil combine_stencils(const VertexStencil* const* stencils, const double* weights, int n) {
  // At most 4 stencils of 4 entries: a fixed buffer, merged by id.
  std::pair<index_t, double> terms[16];
  int count = 0;
  for (int s = 0; s < n && s < 4; ++s)
    for (int k = 0; k < 4; ++k) {
      const index_t id = stencils[s]->ids[k];
      if (id < 0) continue;
      const double w = weights[s] * stencils[s]->weights[k];
      int i = 0;
      while (i < count && terms[i].first != id) ++i;
      if (i == count) terms[count++] = {id, 0.0};
      terms[i].second += w;
    }
  // Largest weights first (ties by id, for reproducibility); insertion sort
  // of at most 16 terms.
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0; --j) {
      const auto& x = terms[j];
      const auto& y = terms[j - 1];
      if (x.second > y.second || (x.second == y.second && x.first < y.first)) std::swap(terms[j], terms[j - 1]);
      else break;
    }
  VertexStencil out;
  double total = 0;
  const int keep = std::min(count, 4);
  for (int i = 0; i < keep; ++i) total += terms[i].second;
  for (int i = 0; i < keep; ++i) {
    out.ids[i] = terms[i].first;
    out.weights[i] = total != 0 ? terms[i].second / total : 1.0 / keep;
  }
  return out;
}

}  // namespace femorph
