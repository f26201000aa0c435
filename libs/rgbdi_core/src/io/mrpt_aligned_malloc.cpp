// rgbdi's definition of mrpt::aligned_malloc: MRPT 2.5.8's own behaviour, except that a request
// the heap cannot serve throws std::bad_alloc instead of returning nullptr.
//
// Why a library symbol is defined here (fuzzing finding 9, doc/robustness.md): MRPT's
// aligned_allocator_cpp11::allocate() returns what mrpt::aligned_malloc returns, unchecked, to
// std::vector, which then writes its elements through the null pointer. Every MRPT matrix
// (CMatrixDynamic: a 3-D scan's range image and its other layers, CMatrixF of old scans) and
// aligned vector allocates through it while it deserialises, with the sizes stored in the file:
// a damaged rawlog asking for terabytes made Release rgbdi-slam die of SIGSEGV inside
// CObservation3DRangeScan::serializeFrom instead of stopping at the damaged record. Checking sizes
// before MRPT allocates cannot be complete: the class of each stored object is itself data (any
// of MRPT's registered serialisable classes can be named by a damaged record and is
// deserialised before rgbdi sees it), and CArchive offers no hook between reading a size and
// allocating it. std::bad_alloc is what std::vector's allocator contract expects on failure;
// MRPT's CArchive passes it through, and RawlogSource turns it into its documented refusal
// ("FILE record N: corrupt record (std::bad_alloc)", exit 3 of rgbdi-slam).
//
// Scope: the definition lives in the executable (this object is linked into every program that
// uses RawlogSource); the dynamic linker binds MRPT's libraries, which call it through their PLT,
// to it. Successful allocations are unchanged (the same rounding and aligned_alloc as MRPT), so
// mrpt::aligned_free (free()) still matches. Tested by
// MrptAlignedMalloc.* (tests/io/test_rawlog_source.cpp).
#include "io/mrpt_aligned_malloc.h"

#include <mrpt/core/aligned_allocator.h>

#include <cstdlib>
#include <limits>
#include <new>

void* mrpt::aligned_malloc(size_t size, size_t alignment) {
  // MRPT: "size must be an integral multiple of alignment".
  if (alignment != 0 && size % alignment != 0) {
    if (size > std::numeric_limits<size_t>::max() - alignment) throw std::bad_alloc();
    size = (size / alignment + 1) * alignment;
  }
  void* p = ::aligned_alloc(alignment, size);
  if (p == nullptr && size != 0) throw std::bad_alloc();
  return p;
}

namespace rgbdi::io {

bool mrptAllocationFailureThrows() { return true; }

}  // namespace rgbdi::io
