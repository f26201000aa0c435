// The contract between a fuzz target (fuzz_*.cpp) and its two drivers: libFuzzer (RGBDI_FUZZ
// build, clang) and replay_main.cpp (normal build, any compiler, run by ctest).
//
// A target defines LLVMFuzzerTestOneInput(), which feeds one input to a reader of outside data
// and swallows the typed exceptions the reader documents (a clean refusal is the right answer to
// bad input; a crash, a sanitizer report, a hang or an escaping exception of another kind is a
// finding), and rgbdiFuzzSeeds(), which builds its seed inputs from the project's own writers
// and test data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace rgbdi::fuzz {

/// Valid inputs the target's reader accepts (the start of the corpus).
std::vector<std::string> rgbdiFuzzSeeds();

/// Writes `bytes` to a file private to this process and target (`tag`) and returns its path:
/// for readers that only take a path. Overwritten by the next call with the same tag.
std::string writeScratchFile(const std::string& tag, const std::uint8_t* data, std::size_t size);

/// Reads a whole file (seed generation).
std::string readFileBytes(const std::string& path);

/// A fresh scratch directory for seed generation (removed by the caller).
std::string scratchDir(const std::string& tag);

}  // namespace rgbdi::fuzz
