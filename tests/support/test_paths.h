// Where a test finds the source tree (scenarios, fixtures, scripts) and the built programs
// (hilrig, dut_emu). The two folders are compiled into one translation unit
// (tests/support/test_paths.cc) rather than into every test, so that every other test's object
// file is the same whichever folder the repository is cloned into, and compiler caches share it.
#pragma once

#include <string>

namespace hilrig::test_support {

// The repository's top folder, absolute, without a trailing slash. Cannot fail; does not read the
// environment.
std::string SourceDir();

// The folder the build puts its programs in (build/bin), absolute, without a trailing slash.
std::string BinDir();

}  // namespace hilrig::test_support
