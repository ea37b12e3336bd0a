#include "vtkFEMorphHeapReuse.h"

#include <mutex>

// glibc's malloc only (AddressSanitizer replaces it).
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define FEMORPH_TUNE_GLIBC_MALLOC 1
#include <malloc.h>
#endif

#if FEMORPH_TUNE_GLIBC_MALLOC
namespace
{
std::mutex ScopeMutex;
int OpenScopes = 0; // nested or concurrent filters: the last one restores
}
#endif

vtkFEMorphHeapReuse::vtkFEMorphHeapReuse()
{
#if FEMORPH_TUNE_GLIBC_MALLOC
  const std::lock_guard<std::mutex> lock(ScopeMutex);
  if (OpenScopes++ == 0)
  {
    mallopt(M_MMAP_MAX, 0);             // large blocks from the heap, reused once freed
    mallopt(M_TRIM_THRESHOLD, 1 << 30); // freed memory stays mapped
  }
#endif
}

vtkFEMorphHeapReuse::~vtkFEMorphHeapReuse()
{
#if FEMORPH_TUNE_GLIBC_MALLOC
  const std::lock_guard<std::mutex> lock(ScopeMutex);
  if (--OpenScopes == 0)
  {
    mallopt(M_MMAP_MAX, 65536);            // glibc's DEFAULT_MMAP_MAX
    mallopt(M_TRIM_THRESHOLD, 128 * 1024); // glibc's DEFAULT_TRIM_THRESHOLD
    malloc_trim(0);
  }
#endif
}

bool vtkFEMorphHeapReuse::Supported()
{
#if FEMORPH_TUNE_GLIBC_MALLOC
  return true;
#else
  return false;
#endif
}
