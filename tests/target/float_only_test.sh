#!/usr/bin/env bash
# The target has a single-precision FPU: double arithmetic there is a library call of hundreds of
# cycles. Lists every function of the firmware image that calls the soft-double routines
# (__aeabi_d*, integer-to-double and float-to-double conversions) and fails on any outside the
# configuration's decoding, which reads the link's doubles once per session. Skips (77) without
# the cross compiler.
# Usage: float_only_test.sh SOURCE_DIR
set -euo pipefail

source_dir=$1
source "$(dirname "$0")/target_image.sh"
require_tools arm-none-eabi-g++

work_dir=$(mktemp -d)
trap 'rm -rf "$work_dir"' EXIT
target_images "$source_dir" "$work_dir/build"

arm-none-eabi-objdump -d -C "$image_dir/dut_fw_stm32f405.elf" |
  awk '/^[0-9a-f]+ <.*>:$/ { function_name = substr($0, index($0, "<")) }
       /\tbl\t.*<__aeabi_(d[a-z0-9]*|[ui]2d|[ul]l2d|ul2d|f2d)>/ { calls[function_name]++ }
       END { for (f in calls) print calls[f] "\t" f }' | sort -rn >"$work_dir/callers"
echo "functions calling soft double:"
cat "$work_dir/callers"
# The configuration's decoding and the runtime's own helpers (llround, the routines themselves).
if grep -v -E 'hilrig::dut_fw::dut_config_internal::|hilrig::dut_fw::DecodeDutConfig<float>\(|hilrig::dut_link::SerialDutSession::OnConfig\(|hilrig::dut_fw::DutCoreController<float>::Configure\(|<llround>|<__aeabi_' \
  "$work_dir/callers"; then
  echo "FAIL: double arithmetic outside the configuration's decoding (above)"
  exit 1
fi
echo "float only: every double operation is in the configuration's decoding"
