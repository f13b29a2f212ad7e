#!/usr/bin/env bash
# The target_image fixture: builds the firmware images once per ctest run, in a fresh tree at
# IMAGE_DIR, for the target tests that run them (they find it through HILRIG_TARGET_IMAGE_DIR).
# Skips (77) without the cross compiler; the tests then skip on their own.
# Usage: build_image_fixture.sh SOURCE_DIR IMAGE_DIR
set -euo pipefail

source_dir=$1
image_dir=$2
source "$(dirname "$0")/target_image.sh"
require_tools arm-none-eabi-g++
rm -rf "$image_dir"
mkdir -p "$(dirname "$image_dir")"
build_target_image "$source_dir" "$image_dir"
ls -l "$image_dir"/*.elf
