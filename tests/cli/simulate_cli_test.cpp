// 'asynevo simulate --list' (what scripts such as the evaluation matrix check names against) and the
// required options of 'asynevo simulate'.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "cli_test_util.hpp"

namespace asynevo::testing {
namespace {

TEST(SimulateCli, ListNamesEveryBuiltInKindOnItsOwnLine) {
  const CommandResult r = runAsynevo("simulate --list");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream lines(r.output);
  std::string line;
  std::vector<std::string> kinds;
  while (std::getline(lines, line)) kinds.push_back(line.substr(0, line.find(':')));
  EXPECT_EQ(kinds, (std::vector<std::string>{"sensors", "noise-levels", "scenes", "motions"})) << r.output;
  for (const char* name : {" davis346", " gen4", " medium", " boxes ", " photo", " 6dof", " slow-start"})
    EXPECT_NE(r.output.find(name), std::string::npos) << name << " missing in:\n" << r.output;
}

TEST(SimulateCli, SceneMotionAndOutAreRequiredWithoutList) {
  const CommandResult r = runAsynevo("simulate --motion 6dof --out /tmp/never_written");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--scene"), std::string::npos) << r.output;
  const CommandResult r2 = runAsynevo("simulate --scene boxes --motion 6dof");
  EXPECT_NE(r2.exit_code, 0);
  EXPECT_NE(r2.output.find("--out"), std::string::npos) << r2.output;
}

}  // namespace
}  // namespace asynevo::testing
