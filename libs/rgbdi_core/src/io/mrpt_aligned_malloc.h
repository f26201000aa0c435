// Private to the io stage: rgbdi's definition of mrpt::aligned_malloc (mrpt_aligned_malloc.cpp).
#pragma once

namespace rgbdi::io {

/// True: mrpt::aligned_malloc throws std::bad_alloc instead of returning nullptr in this process.
/// RawlogSource calls it so that the linker takes mrpt_aligned_malloc.cpp (and with it the
/// definition) from the static library into every program that reads rawlogs.
bool mrptAllocationFailureThrows();

}  // namespace rgbdi::io
