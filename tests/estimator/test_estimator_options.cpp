// EstimatorOptions: the solver keys added for CPU cost (issue 13) are read with their ranges,
// and their defaults equal share/config.ini.
#include <gtest/gtest.h>

#include <string>

#include "rgbdi/estimator/estimator_options.h"
#include "testing/fixtures.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::estimator::EstimatorOptions;

TEST(EstimatorOptions, TheRemovedCeresLineSearchKeyIsRefused) {
  // The window solver clamps steps onto the inverse-depth bound; the key of Ceres' projected
  // line search has no meaning any more and must not be accepted silently.
  IniReader old = IniReader::fromText("[estimator]\nbound_line_search_iterations = 20\n", "e.ini");
  EstimatorOptions::load(old);
  try {
    old.checkNoUnknownKeys();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bound_line_search_iterations"), std::string::npos)
        << e.what();
  }
}

TEST(EstimatorOptions, TheSolverFunctionToleranceDefaultEqualsTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const EstimatorOptions o = EstimatorOptions::load(ini);
  EXPECT_EQ(o.solver_function_tolerance, EstimatorOptions().solver_function_tolerance);
  EXPECT_EQ(o.solver_function_tolerance, 1e-3);
  EXPECT_EQ(o.solver_function_tolerance_no_depth,
            EstimatorOptions().solver_function_tolerance_no_depth);
  EXPECT_EQ(o.solver_function_tolerance_no_depth, 1e-6);
}

TEST(EstimatorOptions, SolverFunctionToleranceIsReadAndOutOfRangeNamesTheKey) {
  IniReader ok = IniReader::fromText("[estimator]\nsolver_function_tolerance = 1e-6\n", "e.ini");
  EXPECT_EQ(EstimatorOptions::load(ok).solver_function_tolerance, 1e-6);
  IniReader ok2 =
      IniReader::fromText("[estimator]\nsolver_function_tolerance_no_depth = 0.01\n", "e.ini");
  EXPECT_EQ(EstimatorOptions::load(ok2).solver_function_tolerance_no_depth, 0.01);
  for (const std::string key :
       {"solver_function_tolerance", "solver_function_tolerance_no_depth"}) {
    for (const char* value : {"0", "0.5"}) {
      IniReader bad = IniReader::fromText("[estimator]\n" + key + " = " + value + "\n", "bad.ini");
      try {
        EstimatorOptions::load(bad);
        FAIL() << "expected ConfigError for " << key << " = " << value;
      } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("bad.ini"), std::string::npos) << msg;
        EXPECT_NE(msg.find(key), std::string::npos) << msg;
      }
    }
  }
}

TEST(EstimatorOptions, NonKeyframeUpdateDefaultEqualsTheShippedConfigAndIsChecked) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  EXPECT_EQ(EstimatorOptions::load(ini).non_keyframe_update,
            EstimatorOptions().non_keyframe_update);
  EXPECT_EQ(EstimatorOptions().non_keyframe_update, "single_step");
  IniReader full = IniReader::fromText("[estimator]\nnon_keyframe_update = full\n", "e.ini");
  EXPECT_EQ(EstimatorOptions::load(full).non_keyframe_update, "full");
  IniReader bad = IniReader::fromText("[estimator]\nnon_keyframe_update = none\n", "bad.ini");
  try {
    EstimatorOptions::load(bad);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.ini"), std::string::npos) << msg;
    EXPECT_NE(msg.find("non_keyframe_update"), std::string::npos) << msg;
  }
}
