// Acceptance of the multi-process lockstep mode: `hilrig run balloon_grasp --dut process` writes
// a trace and a CAN log byte-identical to the in-process run, on the shared-memory link (the
// default) and on TCP. Runs the real binaries (~10 s).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace {

namespace fs = std::filesystem;

using hilrig::host::ReadFile;

int RunHilrig(const fs::path& out_dir, const std::string& dut) {
  const std::string command =
      ::hilrig::test_support::BinDir() + "/hilrig run " + ::hilrig::test_support::SourceDir() +
      "/scenarios/balloon_grasp.textproto --out " + out_dir.string() + " --dut " + dut +
      " --no-reference > " + (out_dir.string() + ".log") + " 2>&1";
  return std::system(command.c_str());
}

TEST(ProcessDutAcceptanceTest, BalloonGraspTraceAndCanLogAreByteIdenticalToInProcess) {
  const fs::path root =
      fs::temp_directory_path() / ("hilrig_process_dut_" + std::to_string(::getpid()));
  fs::create_directories(root);
  ASSERT_EQ(RunHilrig(root / "inproc", "inproc"), 0) << ReadFile(root / "inproc.log");
  ASSERT_EQ(RunHilrig(root / "process", "process"), 0) << ReadFile(root / "process.log");
  ASSERT_EQ(RunHilrig(root / "tcp", "process --dut-link tcp"), 0) << ReadFile(root / "tcp.log");
  const std::string trace = ReadFile(root / "inproc" / "trace.csv");
  const std::string can_log = ReadFile(root / "inproc" / "can.log");
  ASSERT_GT(trace.size(), 100'000u);  // a real run, not two empty files
  ASSERT_GT(can_log.size(), 100'000u);
  EXPECT_TRUE(trace == ReadFile(root / "process" / "trace.csv")) << "trace.csv differs";
  EXPECT_TRUE(can_log == ReadFile(root / "process" / "can.log")) << "can.log differs";
  EXPECT_TRUE(trace == ReadFile(root / "tcp" / "trace.csv")) << "trace.csv differs on TCP";
  EXPECT_TRUE(can_log == ReadFile(root / "tcp" / "can.log")) << "can.log differs on TCP";
  const std::string report = ReadFile(root / "process" / "report.json");
  EXPECT_NE(report.find("link_commands_received"), std::string::npos);
  fs::remove_all(root);
}

}  // namespace
