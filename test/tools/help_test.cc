// `--help` of every built tool: exit code 0, a usage line and an example naming the tool, only
// the tool's own flags (no glog/gflags internals), and at most 40 lines (one screen).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../common/run_command.h"

namespace hdvio {
namespace {

// Written by CMake: one built tool per line.
std::vector<std::string> toolBinaries() {
  std::vector<std::string> tools;
  std::ifstream list(HDVIO_TOOL_LIST);
  for (std::string t; std::getline(list, t);)
    if (!t.empty()) tools.push_back(t);
  return tools;
}

class ToolHelp : public ::testing::TestWithParam<std::string> {};

TEST_P(ToolHelp, FitsOnOneScreenWithUsageAndExample) {
  const std::string binary = GetParam();
  const std::string name = std::filesystem::path(binary).filename().string();
  for (const char* flag : {"--help", "-h"}) {
    const test::CommandOutcome o = test::runCommand(binary + " " + flag);
    EXPECT_EQ(o.exit_code, 0) << flag << "\n" << o.output;
    EXPECT_EQ(o.output.rfind("usage: " + name + " ", 0), 0u) << o.output;
    EXPECT_NE(o.output.find("\nexample: " + name + " "), std::string::npos) << o.output;
    EXPECT_LE(std::count(o.output.begin(), o.output.end(), '\n'), 40) << o.output;
    // Library flags stay behind --helpfull.
    for (const char* internal : {"--logtostderr", "--v=", "--flagfile", "--tryfromenv", "--minloglevel"})
      EXPECT_EQ(o.output.find(internal), std::string::npos) << internal << "\n" << o.output;
    EXPECT_NE(o.output.find("--helpfull"), std::string::npos) << o.output;
  }
  // --helpfull still lists everything.
  const test::CommandOutcome full = test::runCommand(binary + " --helpfull");
  EXPECT_EQ(full.exit_code, 0);
  EXPECT_NE(full.output.find("-flagfile"), std::string::npos);
}

// A flag the tool does not have is bad input: one error line, exit code 2 (gflags alone: 1).
TEST_P(ToolHelp, UnknownFlagIsBadInput) {
  const test::CommandOutcome o = test::runCommand(GetParam() + " --no_such_flag=1");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_EQ(o.output.rfind("error: --no_such_flag: unknown flag (", 0), 0u) << o.output;
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
}

INSTANTIATE_TEST_SUITE_P(AllTools, ToolHelp, ::testing::ValuesIn(toolBinaries()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return std::filesystem::path(info.param).filename().string();
                         });

TEST(ToolHelpList, EveryToolIsBuiltAndListed) { EXPECT_GE(toolBinaries().size(), 13u); }

TEST(ToolFlagValues, WrongTypeIsBadInput) {
  std::string eval;
  for (const auto& t : toolBinaries())
    if (std::filesystem::path(t).filename() == "hdvio_eval") eval = t;
  ASSERT_FALSE(eval.empty());
  for (const char* args : {" --max_time_diff=abc", " --max_time_diff abc", " --max-time-diff=abc"}) {
    const test::CommandOutcome o = test::runCommand(eval + args);
    EXPECT_EQ(o.exit_code, 2) << args << "\n" << o.output;
    EXPECT_EQ(o.output, "error: --max_time_diff: 'abc' is not a valid double (hdvio_eval --help lists the flags)\n");
  }
  EXPECT_EQ(test::runCommand(eval + " --max_time_diff").exit_code, 2);  // value missing
}

}  // namespace
}  // namespace hdvio
