# Sourced by the target tests: the checks for the tools they need, and the firmware image built in
# a fresh tree of the test's own (so a test never runs an image some other build left behind).

# Exits 77 (ctest's skip) naming the first tool in "$@" that is not installed.
require_tools() {
  local tool
  for tool in "$@"; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool not installed"; exit 77; }
  done
}

# Builds the images of SOURCE_DIR into BUILD_DIR (BUILD_DIR/dut_fw_stm32f405.elf, ...), or fails
# the test with the end of the build's log.
build_target_image() {
  local source_dir=$1 build_dir=$2
  if ! HILRIG_TARGET_BUILD_DIR=$build_dir "$source_dir/scripts/build-target" -j1 \
    >"$build_dir.log" 2>&1; then
    echo "FAIL: the firmware image does not build"
    tail -20 "$build_dir.log"
    exit 1
  fi
}
