#!/usr/bin/env bash
# Runs a shipped scene with the firmware image in the loop on QEMU (`hilrig run --dut qemu`) and
# holds it to what the scene asks of any DUT: every envelope (the target's work envelope included)
# passed, but those a cut leaves not evaluated, a report with the target section, and a trace within a stated tolerance of
# the same firmware in single precision on the host (`--dut inproc-float`). Byte identity is not
# expected: newlib's libm and the target compiler's contractions round differently from glibc's.
# QEMU's USART keeps such a run below real time (about 0.2x), so DURATION_S (when given) runs only
# the scene's first seconds (`--duration-s`); HILRIG_TARGET_FULL_SCENES=1 runs the whole scene.
# The image is the target_image fixture's (tests/target/target_image.sh). Skips (77) without
# qemu-system-arm or the cross compiler.
# Usage: qemu_scene_test.sh SOURCE_DIR BIN_DIR SCENE [DURATION_S]
set -euo pipefail

source_dir=$1
bin_dir=$2
scene=$3
cut=()
if [[ -n ${4:-} && ${HILRIG_TARGET_FULL_SCENES:-0} != 1 ]]; then cut=(--duration-s "$4"); fi
source "$(dirname "$0")/target_image.sh"
require_tools qemu-system-arm arm-none-eabi-g++

work_dir=$(mktemp -d)
trap 'rm -rf "$work_dir"' EXIT
target_images "$source_dir" "$work_dir/build"
spec=$source_dir/scenarios/$scene.textproto

# True when run NAME (exit STATUS) met every envelope it could evaluate: exit 0, or, in a scene
# cut short, exit 1 with every envelope that is not a pass NOT EVALUATED (its window opens after
# the cut) and the run completed.
passed_its_cut() {
  local name=$1 status=$2
  [[ $status == 0 ]] && return 0
  [[ $status == 1 && ${#cut[@]} -gt 0 ]] || return 1
  ! grep -qE '^(FAIL|DUT FAULT)' "$work_dir/$name.out" &&
    grep -q '"stop_kind": "STOP_COMPLETED"' "$work_dir/$name/report.json"
}

status=0
"$bin_dir/hilrig" run "$spec" --dut qemu --target-image "$image_dir/dut_fw_stm32f405.elf" \
  --no-reference "${cut[@]}" --out "$work_dir/qemu" >"$work_dir/qemu.out" 2>&1 || status=$?
grep -E '^(PASS|FAIL|NOT EVALUATED|----)|^target |^real-time factor' "$work_dir/qemu.out" || true
if ! passed_its_cut qemu "$status"; then
  echo "FAIL: $scene with --dut qemu exited $status"
  tail -20 "$work_dir/qemu.out"
  exit 1
fi
for field in work_p50_cycles work_p99_cycles work_max_cycles flash_used_bytes ram_used_bytes; do
  grep -q "\"$field\"" "$work_dir/qemu/report.json" ||
    { echo "FAIL: report.json has no target $field"; exit 1; }
done
# QEMU's counts are its virtual time, not cycles of a real core: the report and the line say so.
grep -q '"emulated_core": true' "$work_dir/qemu/report.json" ||
  { echo "FAIL: report.json does not mark the target's counts as QEMU's"; exit 1; }
grep -q "^target .*SysTick counts of QEMU's virtual time (not cycles" "$work_dir/qemu.out" ||
  { echo "FAIL: the target line calls QEMU's counts cycles"; exit 1; }

# A lockstep step the board took without its announced sensor bytes is not comparable: say so
# rather than report a tolerance miss.
missing=$(grep -A1 '"name": "dut_bridge_bytes_missing"' "$work_dir/qemu/report.json" |
  sed -n 's/.*"value": *\([0-9]*\).*/\1/p')
if [[ ${missing:-0} != 0 ]]; then
  echo "FAIL: the board stepped without $missing announced bridge bytes (dut_bridge_bytes_missing)"
  exit 1
fi

status=0
"$bin_dir/hilrig" run "$spec" --dut inproc-float --no-reference "${cut[@]}" --out "$work_dir/float" \
  >"$work_dir/float.out" 2>&1 || status=$?
passed_its_cut float "$status" || { echo "FAIL: $scene with --dut inproc-float exited $status"; exit 1; }

# The largest |qemu - float| of each column with a tolerance, and where it is.
awk -F, -v tolerances="x_m=1e-4 y_m=1e-4 z_m=1e-4 position_error_m=1e-4 thrust0_n=5e-3 \
thrust1_n=5e-3 thrust2_n=5e-3 thrust3_n=5e-3 grasp_force_n=5e-3 grasp_force_estimate_n=2e-2 \
servo_command_rad=1e-4 load_n=5e-3" '
  BEGIN { n = split(tolerances, pairs, " ")
          for (i = 1; i <= n; ++i) { split(pairs[i], kv, "="); limit[kv[1]] = kv[2] } }
  FNR == 1 { for (i = 1; i <= NF; ++i) name[i] = $i; columns = NF; next }
  NR == FNR { for (i = 1; i <= NF; ++i) float_value[FNR, i] = $i; rows = FNR; next }
  { if (FNR > rows) { extra = 1; next }
    for (i = 2; i <= NF; ++i) if (name[i] in limit) {
      d = $i - float_value[FNR, i]; if (d < 0) d = -d
      if (d > worst[i] || !(i in worst)) { worst[i] = d; at[i] = $1 } } }
  END { if (FNR != rows || extra) { print "FAIL: the traces have different lengths"; exit 1 }
        bad = 0
        for (i = 2; i <= columns; ++i) if (name[i] in limit) {
          verdict = worst[i] <= limit[name[i]] ? "ok  " : "FAIL"; if (verdict == "FAIL") bad = 1
          printf "%s %-24s max |qemu - float| %.3g at %s s (tolerance %s)\n",
                 verdict, name[i], worst[i], at[i], limit[name[i]] }
        exit bad }' "$work_dir/float/trace.csv" "$work_dir/qemu/trace.csv"
echo "qemu scene: $scene passed with the firmware on QEMU, within tolerance of --dut inproc-float"
