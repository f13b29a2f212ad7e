#!/usr/bin/env bash
# Kills QEMU in the middle of a `hilrig run --dut qemu` and holds the runner to what it promises
# for a DUT that dies: the run ends within a second of the kill, exits 1, and leaves a complete
# folder whose report names the failure (stop_kind STOP_DUT_FAILED, the emulator and its signal)
# next to the trace and CAN log written so far. Skips (77) without qemu-system-arm or the cross
# compiler.
# Usage: qemu_kill_test.sh SOURCE_DIR BIN_DIR
set -euo pipefail

source_dir=$1
bin_dir=$2
source "$(dirname "$0")/target_image.sh"
require_tools qemu-system-arm arm-none-eabi-g++ pgrep

make_work_dir_for_a_run
target_images "$source_dir" "$work_dir/build"

out=$work_dir/run
"$bin_dir/hilrig" run "$source_dir/scenarios/balloon_grasp.textproto" --dut qemu \
  --target-image "$image_dir/dut_fw_stm32f405.elf" --no-reference --out "$out" \
  >"$work_dir/run.out" 2>&1 &
run_pid=$!

# The kill comes once the run is under way: QEMU is the runner's child and the trace has rows (it
# is flushed every few wall seconds). Bounded: a run that never gets there fails the test.
qemu_pid=
for _ in $(seq 600); do
  qemu_pid=$(pgrep -P "$run_pid" qemu-system-arm || true)
  [[ -n $qemu_pid && -f $out/trace.csv && $(wc -l <"$out/trace.csv") -gt 10 ]] && break
  kill -0 "$run_pid" 2>/dev/null || { echo "FAIL: the run ended before the kill"; cat "$work_dir/run.out"; exit 1; }
  sleep 0.1
done
[[ -n $qemu_pid ]] || { echo "FAIL: no qemu-system-arm under the run"; exit 1; }

killed_ns=$(date +%s%N)
kill -9 "$qemu_pid"
status=0
for _ in $(seq 100); do
  kill -0 "$run_pid" 2>/dev/null || break
  sleep 0.02
done
ended_ns=$(date +%s%N)
if kill -0 "$run_pid" 2>/dev/null; then
  echo "FAIL: the run still goes 2 s after qemu was killed"
  exit 1
fi
wait "$run_pid" || status=$?
run_pid=
elapsed_ms=$(((ended_ns - killed_ns) / 1000000))
echo "qemu killed: the run ended after ${elapsed_ms} ms with exit $status"
tail -3 "$work_dir/run.out"

[[ $status == 1 ]] || { echo "FAIL: exit $status, expected 1"; exit 1; }
((elapsed_ms < 1000)) || { echo "FAIL: ${elapsed_ms} ms from the kill to the end"; exit 1; }
grep -q '"stop_kind": *"STOP_DUT_FAILED"' "$out/report.json" ||
  { echo "FAIL: report.json does not say STOP_DUT_FAILED"; exit 1; }
grep -q "emulator killed by signal 9" "$out/report.json" ||
  { echo "FAIL: report.json does not name the emulator's end"; exit 1; }
for file in trace.csv can.log junit.xml; do
  [[ -s $out/$file ]] || { echo "FAIL: $file is missing or empty"; exit 1; }
done
echo "qemu kill: named stop, complete folder"
