// Runs the built hilrig binary as a child process, for what an in-process run cannot show: where
// standard output really goes (/dev/full), or an input that would block the whole process (a
// FIFO). A command that hangs is killed after a bound, so a test fails instead of hanging.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {

struct ProcessResult {
  int exit_code;    // 128 + the signal when it was killed; 124 when the bound ran out
  std::string err;  // what it wrote to standard error
};

// `arguments` follow "hilrig" in a shell command line and may redirect standard input and output
// (">/dev/full", "<file"); standard error is kept in `err_file` and returned.
inline ProcessResult RunHilrig(const std::string& arguments,
                               const std::filesystem::path& err_file) {
  const std::string command = "timeout -k 2 10 " + ::hilrig::test_support::BinDir() + "/hilrig " +
                              arguments + " 2>" + err_file.string();
  const int status = std::system(command.c_str());
  const int exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return {exit_code, ReadFile(err_file)};
}

}  // namespace hilrig::host
