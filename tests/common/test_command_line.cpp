// The shared option parser of the tools (TCLAP underneath): spellings, --opt=value, aliases,
// errors, --help/--version.
#include <gtest/gtest.h>

#include "rgbdi/common/command_line.h"

namespace rgbdi {
namespace {

struct Parsed {
  std::string out, mode, colour;
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
  cl.value("--colour-topic,--color-topic", &p.colour);
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
  EXPECT_EQ(run({"--mode", "-x"}).mode, "-x");                        // a value may start with '-'
  EXPECT_EQ(run({"--mode", "a b"}).mode, "a b");
  EXPECT_EQ(run({"--color-topic=/c"}).colour, "/c");  // either spelling of an alias
  EXPECT_EQ(run({"--colour-topic", "/d"}).colour, "/d");
}

TEST(CommandLine, DoubleDashLeavesNoTraceForTheNextParse) {
  // TCLAP keeps "--" in a process-wide static; CommandLine never hands it over.
  EXPECT_EQ(run({"a", "--", "--out", "-q"}).positional,
            (std::vector<std::string>{"a", "--out", "-q"}));
  const Parsed p = run({"--out", "o", "-q"});
  EXPECT_EQ(p.out, "o");
  EXPECT_TRUE(p.quiet);
  EXPECT_EQ(usageError({"--ignore_rest", "--out", "x"}), "unknown option '--ignore_rest'");
  EXPECT_EQ(run({"--out", "y"}).out, "y");
}

TEST(CommandLine, ErrorsNameTheOption) {
  EXPECT_EQ(usageError({"--bogus"}), "unknown option '--bogus'");
  EXPECT_EQ(usageError({"--bogus=1"}), "unknown option '--bogus'");
  EXPECT_EQ(usageError({"--out"}), "--out needs a value");
  EXPECT_EQ(usageError({"--quiet=yes"}), "--quiet takes no value (got '--quiet=yes')");
  EXPECT_EQ(usageError({"--tol", "0"}), "--tol needs a positive number, got '0'");
  EXPECT_EQ(usageError({"--tol=abc"}), "--tol needs a positive number, got 'abc'");
  EXPECT_EQ(usageError({"-o"}), "--out needs a value");
  EXPECT_EQ(usageError({"--out="}), "--out needs a value");  // not the next argument
  EXPECT_EQ(usageError({"--out=", "x"}), "--out needs a value");
  EXPECT_EQ(usageError({"-z"}), "unknown option '-z'");
  EXPECT_EQ(usageError({"x", "--bogus"}), "unknown option '--bogus'");
  EXPECT_EQ(usageError({"--out", "a", "-o", "b"}), "--out is given more than once");
  EXPECT_EQ(usageError({"-q", "--quiet"}), "--quiet is given more than once");
  EXPECT_EQ(usageError({"--colour-topic", "a", "--color-topic=b"}),
            "--colour-topic and --color-topic are the same option; give it once");
  EXPECT_EQ(usageError({"a*b"}), "cannot read argument 'a*b' (the option parser reserves '*')");
}

TEST(CommandLine, SetterRejectionsBecomeUsageErrors) {
  CommandLine cl;
  cl.value("--n", [](const std::string& v) { throw std::invalid_argument("--n: bad " + v); });
  const char* argv[] = {"tool", "--n", "7"};
  try {
    cl.parse(3, argv);
    FAIL() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "--n: bad 7");
  }
}

TEST(CommandLine, DeclarationsTclapCannotTakeAreProgrammingErrors) {
  CommandLine cl;
  cl.value("-o,--out", [](const std::string&) {});
  EXPECT_THROW(cl.flag("-q", nullptr), std::logic_error);             // no long name
  EXPECT_THROW(cl.flag("-q,-r,--quiet", nullptr), std::logic_error);  // two short names
  EXPECT_THROW(cl.flag("--verbose,-vv", nullptr), std::logic_error);  // not a short name
  EXPECT_THROW(cl.flag("--out", nullptr), std::logic_error);          // declared already
}

TEST(CommandLine, HelpAndVersionWinOverErrors) {
  EXPECT_EQ(run({"--bogus", "--help"}).outcome, CommandLine::Outcome::Help);
  EXPECT_EQ(run({"-h"}).outcome, CommandLine::Outcome::Help);
  EXPECT_EQ(run({"--out", "--version"}).outcome, CommandLine::Outcome::Version);
  EXPECT_EQ(versionLine("rgbdi-eval"), std::string("rgbdi-eval (rgbdi) ") + rgbdiVersion());
  EXPECT_STREQ(rgbdiVersion(), "0.1.0");  // project(rgbdi VERSION 0.1.0) in CMakeLists.txt
  EXPECT_NE(exitStatusHelp().find("3 damaged input"), std::string::npos);
  EXPECT_EQ(usageErrorLine("rgbdi-sim", "--fps needs a value"),
            "rgbdi-sim: --fps needs a value (see rgbdi-sim --help)\n");
}

}  // namespace
}  // namespace rgbdi
