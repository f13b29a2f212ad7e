#!/usr/bin/env bash
# Builds the STM32F405 image in a fresh build tree and checks that it links and that an image
# which allocates does not: the firmware must run without a heap. Skips (77) without the
# arm-none-eabi cross compiler.
# Usage: no_heap_link_test.sh SOURCE_DIR
set -euo pipefail

source_dir=$1
if ! command -v arm-none-eabi-g++ >/dev/null; then
  echo "SKIP: arm-none-eabi-g++ not installed (gcc-arm-none-eabi, libnewlib-arm-none-eabi)"
  exit 77
fi
build_dir=$(mktemp -d)
trap 'rm -rf "$build_dir"' EXIT
export HILRIG_TARGET_BUILD_DIR=$build_dir

if ! "$source_dir/scripts/build-target" -j1 >"$build_dir/image.log" 2>&1; then
  echo "FAIL: the firmware image does not build"
  tail -20 "$build_dir/image.log"
  exit 1
fi
if "$source_dir/scripts/build-target" -j1 --target heap_probe >"$build_dir/probe.log" 2>&1; then
  echo "FAIL: an image that calls malloc linked"
  exit 1
fi
if ! grep -q "undefined reference to \`__wrap_malloc'" "$build_dir/probe.log"; then
  echo "FAIL: the allocating image failed to build for another reason than the heap guard"
  tail -20 "$build_dir/probe.log"
  exit 1
fi
echo "no heap: the image links, an allocating image fails on __wrap_malloc"
