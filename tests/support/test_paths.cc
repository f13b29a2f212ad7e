// The build's folders, given to this file alone as HILRIG_SOURCE_DIR and HILRIG_BIN_DIR.
#include "tests/support/test_paths.h"

namespace hilrig::test_support {

std::string SourceDir() { return HILRIG_SOURCE_DIR; }

std::string BinDir() { return HILRIG_BIN_DIR; }

}  // namespace hilrig::test_support
