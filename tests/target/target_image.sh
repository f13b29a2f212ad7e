# Sourced by the target tests: the checks for the tools they need, and the firmware images they run:
# the ones the target_image fixture built fresh for this ctest run, or, for a test run by hand,
# images built in a fresh tree of the test's own (never an image some other build left behind).

# Sets work_dir to a fresh folder, removed at exit together with the run whose pid is in run_pid
# (killed if it still runs), for the tests that start `hilrig run` in the background.
make_work_dir_for_a_run() {
  work_dir=$(mktemp -d)
  run_pid=
  trap '[[ -n $run_pid ]] && kill -9 "$run_pid" 2>/dev/null; rm -rf "$work_dir"' EXIT
}

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

# Sets image_dir to the folder of the images the test runs: $HILRIG_TARGET_IMAGE_DIR, which ctest
# sets for the tests that require the target_image fixture (tests/target/build_image_fixture.sh),
# or else BUILD_DIR after building SOURCE_DIR's images into it.
target_images() {
  local source_dir=$1 build_dir=$2
  if [[ -z ${HILRIG_TARGET_IMAGE_DIR:-} ]]; then
    build_target_image "$source_dir" "$build_dir"
    image_dir=$build_dir
    return
  fi
  if [[ ! -f $HILRIG_TARGET_IMAGE_DIR/dut_fw_stm32f405.elf ]]; then
    echo "FAIL: no firmware image in $HILRIG_TARGET_IMAGE_DIR (its fixture, target_image_build," \
      "did not run or failed)"
    exit 1
  fi
  image_dir=$HILRIG_TARGET_IMAGE_DIR
}
