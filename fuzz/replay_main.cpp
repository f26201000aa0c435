// Replay driver of a fuzz target for the normal build (no libFuzzer needed):
//   fuzz_replay_X                     seeds plus deterministic mutations of them (truncations,
//                                     byte flips, seeded): the bounded run of the test suite
//   fuzz_replay_X --truncations-only  seeds and their truncations only
//   fuzz_replay_X FILE|DIR...         every given input (a libFuzzer corpus, a crash file)
//   fuzz_replay_X --write-seeds DIR   writes the seeds as a corpus for libFuzzer (scripts/fuzz.sh)
// Prints the number of inputs run; an input that crashes the reader ends the process abnormally.
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "fuzz_target.h"

namespace {

namespace fs = std::filesystem;

/// RGBDI_FUZZ_TRACE=1: name every input on stderr before it runs (to find the one that fails);
/// RGBDI_FUZZ_SAVE=N:FILE: write input number N to FILE instead of running anything.
struct Trace {
  bool on = std::getenv("RGBDI_FUZZ_TRACE") != nullptr;
  long save_index = -1;
  std::string save_path;
  long index = 0;
  Trace() {
    if (const char* s = std::getenv("RGBDI_FUZZ_SAVE")) {
      const std::string v = s;
      const auto colon = v.find(':');
      if (colon != std::string::npos) {
        save_index = std::stol(v.substr(0, colon));
        save_path = v.substr(colon + 1);
      }
    }
  }
} g_trace;

void runOne(const std::string& bytes) {
  const long n = g_trace.index++;
  if (g_trace.save_index >= 0) {
    if (n == g_trace.save_index) std::ofstream(g_trace.save_path, std::ios::binary) << bytes;
    return;
  }
  if (g_trace.on) std::cerr << "input " << n << " (" << bytes.size() << " bytes)" << std::endl;
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

constexpr int kTruncations = 24;  ///< cut points per seed, spread over its length
constexpr int kFlips = 48;        ///< single-byte mutations per seed
constexpr int kBursts = 8;        ///< 16-byte random overwrites per seed

std::size_t mutateAll(const std::vector<std::string>& seeds, bool truncations_only) {
  std::size_t runs = 0;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const std::string& seed = seeds[s];
    runOne(seed);
    ++runs;
    if (seed.empty()) continue;
    std::mt19937_64 rng(1000 + s);
    for (int k = 1; k <= kTruncations; ++k) {
      runOne(seed.substr(0, seed.size() * static_cast<std::size_t>(k) / (kTruncations + 1)));
      ++runs;
    }
    if (truncations_only) continue;
    std::uniform_int_distribution<std::size_t> pos(0, seed.size() - 1);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int k = 0; k < kFlips; ++k) {
      std::string m = seed;
      m[pos(rng)] = static_cast<char>(byte(rng));
      runOne(m);
      ++runs;
    }
    for (int k = 0; k < kBursts; ++k) {
      std::string m = seed;
      const std::size_t at = pos(rng);
      for (std::size_t i = at; i < std::min(m.size(), at + 16); ++i)
        m[i] = static_cast<char>(byte(rng));
      runOne(m);
      ++runs;
    }
  }
  return runs;
}

}  // namespace

#if defined(__SANITIZE_ADDRESS__)
#define RGBDI_REPLAY_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RGBDI_REPLAY_ASAN 1
#endif
#endif

/// [bytes] address-space limit of a replay, like libFuzzer's -rss_limit_mb: a corrupt size field
/// that makes MRPT or ROS allocate gigabytes (doc/robustness.md, finding 1; 2 and 3 are now refused
/// first) fails as std::bad_alloc, which the readers turn into their refusal, instead of exhausting
/// the machine.
constexpr rlim_t kAddressSpaceLimit = 3ull << 29;  // 1.5 GiB

int main(int argc, char** argv) {
#ifndef RGBDI_REPLAY_ASAN  // ASan reserves terabytes of shadow memory: no limit there
  const rlimit lim{kAddressSpaceLimit, kAddressSpaceLimit};
  setrlimit(RLIMIT_AS, &lim);
#endif
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (!args.empty() && args[0] == "--write-seeds") {
      if (args.size() != 2) throw std::invalid_argument("--write-seeds needs a directory");
      fs::create_directories(args[1]);
      const auto seeds = rgbdi::fuzz::rgbdiFuzzSeeds();
      for (std::size_t i = 0; i < seeds.size(); ++i) {
        std::ofstream f(args[1] + "/seed_" + std::to_string(i), std::ios::binary);
        f << seeds[i];
      }
      std::cout << seeds.size() << " seeds written to " << args[1] << "\n";
      return 0;
    }
    std::size_t runs = 0;
    if (args.empty() || args[0] == "--truncations-only") {
      runs = mutateAll(rgbdi::fuzz::rgbdiFuzzSeeds(), !args.empty());
    } else {
      for (const auto& a : args) {
        std::vector<fs::path> files;
        if (fs::is_directory(a)) {
          for (const auto& e : fs::directory_iterator(a))
            if (e.is_regular_file()) files.push_back(e.path());
          std::sort(files.begin(), files.end());
        } else {
          files.emplace_back(a);
        }
        for (const auto& f : files) {
          runOne(rgbdi::fuzz::readFileBytes(f.string()));
          ++runs;
        }
      }
    }
    std::cout << argv[0] << ": " << runs << " inputs run, none crashed\n";
  } catch (const std::exception& e) {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
