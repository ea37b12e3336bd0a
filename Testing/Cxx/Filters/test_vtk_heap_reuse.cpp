// vtkFEMorphHeapReuse: inside the scope a large block freed and allocated
// again reuses the pages already mapped (no new page faults); after the
// last scope ends, malloc maps fresh pages again (the defaults are back).
#include "vtkFEMorphHeapReuse.h"

#include <gtest/gtest.h>

#include <malloc.h>
#include <sys/resource.h>

#include <cstddef>
#include <cstdlib>

namespace {

constexpr std::size_t kBytes = 64u << 20;  // above glibc's largest mmap threshold (32 MiB)
constexpr long kPages = static_cast<long>(kBytes / 4096);

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// Page faults taken while writing every page of a new block of kBytes.
long faults_of_touching_a_new_block() {
  char* block = static_cast<char*>(std::malloc(kBytes));
  EXPECT_NE(block, nullptr);
  if (!block) return -1;
  volatile char* pages = block;  // the writes must happen
  const long before = minor_faults();
  for (std::size_t i = 0; i < kBytes; i += 4096) pages[i] = 1;
  const long faults = minor_faults() - before;
  std::free(block);
  return faults;
}

/// Whether malloc serves a new block of kBytes with its own mmap().
bool mapped_on_its_own() {
  const std::size_t before = mallinfo2().hblkhd;
  void* volatile block = std::malloc(kBytes);  // volatile: the pair must not be elided
  const bool mapped = mallinfo2().hblkhd >= before + kBytes;
  std::free(block);
  return mapped;
}

}  // namespace

TEST(HeapReuse, FreedBlocksAreReusedInsideTheScopeOnly) {
  if (!vtkFEMorphHeapReuse::Supported()) GTEST_SKIP() << "not glibc's malloc";
  {
    const vtkFEMorphHeapReuse outer;
    EXPECT_FALSE(mapped_on_its_own());
    faults_of_touching_a_new_block();  // maps the pages once
    EXPECT_LT(faults_of_touching_a_new_block(), kPages / 10) << "freed memory was given back inside the scope";
    {
      const vtkFEMorphHeapReuse inner;
    }
    EXPECT_LT(faults_of_touching_a_new_block(), kPages / 10) << "an inner scope restored the defaults";
  }
  EXPECT_TRUE(mapped_on_its_own()) << "large blocks are not mapped on their own again";
  faults_of_touching_a_new_block();
  EXPECT_GT(faults_of_touching_a_new_block(), kPages / 2) << "the defaults were not restored";
}
