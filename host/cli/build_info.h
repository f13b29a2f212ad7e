// Which build of the rig is running, for `hilrig --version` and for what a result records of the
// build that made it: the commit of the source tree and the build type. The definition is written
// by cmake/build_info.cmake at every build, so it follows the tree without a new configure.
#pragma once

#include <string>

namespace hilrig::host {

struct BuildInfo {
  const char* commit;      // 12 hex digits, "-dirty" with uncommitted changes, or "unknown"
  const char* build_type;  // CMAKE_BUILD_TYPE: "Release", "Debug", ...
};

// This binary's build. Cannot fail.
const BuildInfo& ThisBuild();

// "hilrig commit 1a2b3c4d5e6f (Release)".
inline std::string VersionLine() {
  return std::string("hilrig commit ") + ThisBuild().commit + " (" + ThisBuild().build_type + ")";
}

}  // namespace hilrig::host
