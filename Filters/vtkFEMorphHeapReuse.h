/**
 * @class   vtkFEMorphHeapReuse
 * @brief   Keeps freed memory in the process heap while a filter runs
 *
 * Scoped (RAII): while one is alive, glibc's malloc serves large blocks from
 * its heap instead of fresh mmap()s and does not give freed memory back to
 * the system, so the many large temporaries of a run (per-tet arrays, edge
 * heaps, grids, reordered copies of the mesh) reuse pages already mapped
 * instead of faulting in new ones. The last scope to end restores the
 * defaults (M_MMAP_MAX 65536, M_TRIM_THRESHOLD 128 KiB; glibc's dynamic
 * thresholds stay off afterwards) and returns the free memory with
 * malloc_trim(0), so the process's footprint after the filter is what it
 * would be without it.
 *
 * Why: a first write to a fresh page costs a page fault, and a run of
 * FEMorph Improve allocates and frees large arrays many times; with this
 * scope only the growth of the mesh faults new pages in.
 *
 * Elsewhere than glibc (and under AddressSanitizer) it does nothing.
 */
#ifndef vtkFEMorphHeapReuse_h
#define vtkFEMorphHeapReuse_h

#include "FEMorphFiltersModule.h" // For export macro

class FEMORPHFILTERS_EXPORT vtkFEMorphHeapReuse
{
public:
  vtkFEMorphHeapReuse();
  ~vtkFEMorphHeapReuse();
  vtkFEMorphHeapReuse(const vtkFEMorphHeapReuse&) = delete;
  vtkFEMorphHeapReuse& operator=(const vtkFEMorphHeapReuse&) = delete;

  /// Whether this platform's allocator is tuned by the scope (glibc).
  static bool Supported();
};

#endif
