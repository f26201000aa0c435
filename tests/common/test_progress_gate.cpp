// ProgressGate: on a terminal a line per interval of wall time; in a log a line per tenth of the
// work whatever the wall time, never two for the same tenth.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "rgbdi/common/progress_gate.h"

namespace rgbdi {
namespace {

TEST(ProgressGate, TerminalPrintsOncePerInterval) {
  ProgressGate g(true, 1.0);
  EXPECT_FALSE(g.due(0.0, 5.0));  // starts the clock
  EXPECT_FALSE(g.due(0.5, 5.9));  // 0.9 s later
  EXPECT_TRUE(g.due(0.5, 6.0));   // one interval
  EXPECT_FALSE(g.due(0.6, 6.5));
  EXPECT_TRUE(g.due(0.6, 7.25));
  EXPECT_TRUE(g.due(0.6, 9.0));  // the fraction does not matter on a terminal
}

TEST(ProgressGate, LogPrintsEachTenthOnceWhateverTheWallTime) {
  ProgressGate g(false, 1.0);
  // A run reporting every 1 % at 100 lines per second: ten lines, at 10 %, 20 %, ..., 100 %.
  std::vector<int> printed_at;
  for (int i = 0; i <= 100; ++i)
    if (g.due(i / 100.0, i * 0.01)) printed_at.push_back(i);
  EXPECT_EQ(printed_at, (std::vector<int>{10, 20, 30, 40, 50, 60, 70, 80, 90, 100}));
  EXPECT_FALSE(g.due(1.0, 100.0));  // 100 % already printed
}

TEST(ProgressGate, LogSkipsTenthsJumpedOverAndIgnoresUnknownFractions) {
  ProgressGate g(false, 1.0);
  EXPECT_FALSE(g.due(-1.0, 0.0));
  EXPECT_FALSE(g.due(0.0999, 0.0));
  EXPECT_TRUE(g.due(0.35, 0.0));  // from nothing to 35 %: one line, not three
  EXPECT_FALSE(g.due(0.39, 0.0));
  EXPECT_TRUE(g.due(0.7, 0.0));   // 0.7 / 0.1 = 6.999999999999999: still the 70 % step
  EXPECT_FALSE(g.due(0.2, 0.0));  // going back prints nothing
  EXPECT_TRUE(g.due(7.0, 0.0));   // clamped to 100 %
  EXPECT_FALSE(g.due(1.0, 0.0));
}

TEST(ProgressGate, LogStepIsConfigurable) {
  ProgressGate g(false, 1.0, 0.25);
  int lines = 0;
  for (int i = 0; i <= 1000; ++i) lines += g.due(i / 1000.0, 0.0) ? 1 : 0;
  EXPECT_EQ(lines, 4);
}

TEST(ProgressGate, RefusesAnIntervalOrStepOutOfRange) {
  EXPECT_THROW(ProgressGate(true, 0.0), std::invalid_argument);
  EXPECT_THROW(ProgressGate(false, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(ProgressGate(false, 1.0, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi
