// The shared option parser of the tools: spellings, --opt=value, errors, --help/--version.
#include <gtest/gtest.h>

#include "rgbdi/common/command_line.h"

namespace rgbdi {
namespace {

struct Parsed {
  std::string out, mode;
  double tol = 0.0;
  bool quiet = false;
  std::vector<std::string> positional;
  CommandLine::Outcome outcome = CommandLine::Outcome::Run;
};

Parsed run(std::vector<const char*> args) {
  Parsed p;
  CommandLine cl;
  cl.value("-o,--out", &p.out);
  cl.value("--mode", &p.mode);
  cl.value("--tol", [&](const std::string& v) { p.tol = parseNumber("--tol", v, true); });
  cl.flag("-q,--quiet", &p.quiet);
  args.insert(args.begin(), "tool");
  p.outcome = cl.parse(static_cast<int>(args.size()), args.data());
  p.positional = cl.positional();
  return p;
}

std::string usageError(std::vector<const char*> args) {
  try {
    run(std::move(args));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(CommandLine, SeparateAndInlineValuesShortAndLongNamesAndPositionals) {
  const Parsed p = run({"in.bag", "--out=x.rawlog", "--mode", "fast", "-q", "--tol=0.5", "more"});
  EXPECT_EQ(p.outcome, CommandLine::Outcome::Run);
  EXPECT_EQ(p.out, "x.rawlog");
  EXPECT_EQ(p.mode, "fast");
  EXPECT_DOUBLE_EQ(p.tol, 0.5);
  EXPECT_TRUE(p.quiet);
  EXPECT_EQ(p.positional, (std::vector<std::string>{"in.bag", "more"}));
  EXPECT_EQ(run({"-o", "y"}).out, "y");
  EXPECT_EQ(run({"--out=a=b"}).out, "a=b");  // only the first '=' splits
  EXPECT_EQ(run({"--", "--out"}).positional, (std::vector<std::string>{"--out"}));
  EXPECT_EQ(run({"-"}).positional, (std::vector<std::string>{"-"}));  // stdin-like name
}

TEST(CommandLine, ErrorsNameTheOption) {
  EXPECT_EQ(usageError({"--bogus"}), "unknown option '--bogus'");
  EXPECT_EQ(usageError({"--bogus=1"}), "unknown option '--bogus'");
  EXPECT_EQ(usageError({"--out"}), "--out needs a value");
  EXPECT_EQ(usageError({"--quiet=yes"}), "--quiet takes no value (got '--quiet=yes')");
  EXPECT_EQ(usageError({"--tol", "0"}), "--tol needs a positive number, got '0'");
  EXPECT_EQ(usageError({"--tol=abc"}), "--tol needs a positive number, got 'abc'");
}

TEST(CommandLine, HelpAndVersionWinOverErrors) {
  EXPECT_EQ(run({"--bogus", "--help"}).outcome, CommandLine::Outcome::Help);
  EXPECT_EQ(run({"-h"}).outcome, CommandLine::Outcome::Help);
  EXPECT_EQ(run({"--out", "--version"}).outcome, CommandLine::Outcome::Version);
  EXPECT_EQ(versionLine("rgbdi-eval"), std::string("rgbdi-eval (rgbdi) ") + rgbdiVersion());
  EXPECT_STREQ(rgbdiVersion(), "0.1.0");  // project(rgbdi VERSION 0.1.0) in CMakeLists.txt
  EXPECT_NE(exitStatusHelp().find("3 damaged input"), std::string::npos);
}

}  // namespace
}  // namespace rgbdi
