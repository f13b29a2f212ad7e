#!/usr/bin/env bash
# What a signal to `hilrig run --dut qemu` does to the emulator it started. SIGTERM: the run ends
# within a second, exits 1 and reports itself interrupted, and QEMU is gone with it. SIGKILL: the
# runner has no say, yet QEMU dies with it (it is started bound to its parent's death) instead of
# running on at 80 % of a core with its ports open. Skips (77) without qemu-system-arm or the
# cross compiler.
# Usage: qemu_signals_test.sh SOURCE_DIR BIN_DIR
set -euo pipefail

source_dir=$1
bin_dir=$2
source "$(dirname "$0")/target_image.sh"
require_tools qemu-system-arm arm-none-eabi-g++ pgrep

make_work_dir_for_a_run
target_images "$source_dir" "$work_dir/build"

# True while PID is a process that has not ended (a zombie has ended: only its entry is left).
alive() {
  local state
  state=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null) || return 1
  [[ $state != Z ]]
}

# Starts the run into $work_dir/$1 and waits until QEMU runs under it; sets run_pid and qemu_pid.
start_run() {
  "$bin_dir/hilrig" run "$source_dir/scenarios/balloon_grasp.textproto" --dut qemu \
    --target-image "$image_dir/dut_fw_stm32f405.elf" --no-reference --out "$work_dir/$1" \
    >"$work_dir/$1.out" 2>&1 &
  run_pid=$!
  qemu_pid=
  for _ in $(seq 600); do
    qemu_pid=$(pgrep -P "$run_pid" qemu-system-arm || true)
    [[ -n $qemu_pid && -f $work_dir/$1/trace.csv ]] && return 0
    kill -0 "$run_pid" 2>/dev/null || { echo "FAIL: the run ended early"; cat "$work_dir/$1.out"; exit 1; }
    sleep 0.1
  done
  echo "FAIL: no qemu-system-arm under the run"
  exit 1
}

# SIGTERM: ended within a second, interrupted, QEMU gone.
start_run term
sleep 1
sent_ns=$(date +%s%N)
kill -TERM "$run_pid"
for _ in $(seq 100); do
  alive "$run_pid" || break
  sleep 0.01
done
ended_ns=$(date +%s%N)
status=0
wait "$run_pid" || status=$?
run_pid=
elapsed_ms=$(((ended_ns - sent_ns) / 1000000))
echo "SIGTERM: the run ended after ${elapsed_ms} ms with exit $status"
[[ $status == 1 ]] || { echo "FAIL: exit $status, expected 1"; exit 1; }
((elapsed_ms < 1000)) || { echo "FAIL: ${elapsed_ms} ms from SIGTERM to the end"; exit 1; }
grep -q '"stop_kind": "STOP_INTERRUPTED"' "$work_dir/term/report.json" ||
  { echo "FAIL: report.json is not an interrupted run's"; exit 1; }
! alive "$qemu_pid" || { echo "FAIL: qemu (pid $qemu_pid) outlived the run"; exit 1; }

# SIGKILL: no child left after 2 s.
start_run kill
kill -KILL "$run_pid"
wait "$run_pid" 2>/dev/null || true
run_pid=
for _ in $(seq 200); do
  alive "$qemu_pid" || break
  sleep 0.01
done
if alive "$qemu_pid"; then
  echo "FAIL: qemu (pid $qemu_pid) still runs 2 s after its runner was killed"
  kill -9 "$qemu_pid" 2>/dev/null || true
  exit 1
fi
echo "SIGKILL: qemu ended with its runner"
echo "qemu signals: passed"
