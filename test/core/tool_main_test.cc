// runTool: the one error exit of the command-line tools (exit code and the one stderr line).
#include "hdvio/core/tool_main.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace hdvio {
namespace {

struct Exit {
  int code;
  std::string err;
};

Exit run(const std::function<int()>& body, const ToolErrorPolicy& policy = {}) {
  testing::internal::CaptureStderr();
  const int code = runTool(body, policy);
  return {code, testing::internal::GetCapturedStderr()};
}

TEST(RunTool, PassesTheBodysExitCode) {
  EXPECT_EQ(run([] { return 0; }).code, 0);
  const Exit e = run([] { return 3; });
  EXPECT_EQ(e.code, 3);
  EXPECT_EQ(e.err, "");
}

TEST(RunTool, BadInputIsOneLineAndExitCode2) {
  const Exit e = run([]() -> int { throw InputError("a.yaml", 7, "no such key"); });
  EXPECT_EQ(e.code, kExitBadInput);
  EXPECT_EQ(e.err, "error: a.yaml:7: no such key\n");
}

TEST(RunTool, OtherFailuresExitWith1) {
  const Exit e = run([]() -> int { throw std::runtime_error("disk full"); });
  EXPECT_EQ(e.code, 1);
  EXPECT_EQ(e.err, "error: disk full\n");
  // By default std::invalid_argument is a failure like any other.
  const Exit i = run([]() -> int { throw std::invalid_argument("bad width"); });
  EXPECT_EQ(i.code, 1);
  EXPECT_EQ(i.err, "error: bad width\n");
}

TEST(RunTool, PolicyMakesInvalidArgumentBadInputAndPrefixesFailures) {
  const ToolErrorPolicy policy{true, "training failed: "};
  const Exit i = run([]() -> int { throw std::invalid_argument("bad width"); }, policy);
  EXPECT_EQ(i.code, kExitBadInput);
  EXPECT_EQ(i.err, "error: bad width\n");
  const Exit f = run([]() -> int { throw std::runtime_error("CUDA out of memory"); }, policy);
  EXPECT_EQ(f.code, 1);
  EXPECT_EQ(f.err, "error: training failed: CUDA out of memory\n");
  const Exit b = run([]() -> int { throw InputError("", 0, "--out is required"); }, policy);
  EXPECT_EQ(b.code, kExitBadInput);
  EXPECT_EQ(b.err, "error: --out is required\n");
}

}  // namespace
}  // namespace hdvio
