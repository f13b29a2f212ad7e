// A tactile calibration for tests of commands that read one (accuracy, decode): made once per test
// process by `hilrig calibrate` on a map:16 film (about a second), in a folder of the process's own
// (ctest runs each test in its own process, two at a time).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/support/cli_runner.h"

namespace hilrig::host {

// The folder that holds calibration.textproto.
inline const std::filesystem::path& SharedCalibrationDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) /
                                       ("hilrig_tactile_cli_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    const CliResult result =
        Cli({"calibrate", "--out", path.string(), "--field", "map:16", "--seed", "3"});
    EXPECT_EQ(result.exit_code, kExitPass) << result.err;
    return path;
  }();
  return dir;
}

inline std::string SharedCalibrationFile() {
  return (SharedCalibrationDir() / "calibration.textproto").string();
}

}  // namespace hilrig::host
