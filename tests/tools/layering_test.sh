#!/usr/bin/env bash
# Checks that each folder includes only what its library may depend on (the layout table in
# docs/): a quoted #include of a folder outside the allowed list fails with the file, the line and
# the rule. The rules are prefixes of repository paths; a folder's own files are always allowed.
# Usage: layering_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"

failures=0
checked=0

# includes FOLDER: "FILE TARGET" for every quoted include in FOLDER/*.{h,cc} (not its subfolders).
includes() {
  local file line target
  for file in "$1"/*.h "$1"/*.cc; do
    [[ -f $file ]] || continue
    while IFS= read -r line; do
      target=${line#*\"}
      echo "$file ${target%%\"*}"
    done < <(grep -E '^#include "' "$file" || true)
  done
}

# check FOLDER ALLOWED_PREFIX...: every quoted include starts with FOLDER/ or one of the prefixes.
check() {
  local folder=$1
  shift
  local file target allowed ok
  while read -r file target; do
    checked=$((checked + 1))
    ok=0
    for allowed in "$folder/" "$@"; do
      [[ $target == "$allowed"* ]] && ok=1 && break
    done
    if ((!ok)); then
      echo "FAIL: $file includes $target; $folder/ may include only: $*"
      failures=$((failures + 1))
    fi
  done < <(includes "$folder")
}

# forbid FOLDER PREFIX...: no quoted include starts with one of the prefixes.
forbid() {
  local folder=$1
  shift
  local file target prefix
  while read -r file target; do
    checked=$((checked + 1))
    for prefix in "$@"; do
      if [[ $target == "$prefix"* ]]; then
        echo "FAIL: $file includes $target; $folder/ must not include $prefix"
        failures=$((failures + 1))
      fi
    done
  done < <(includes "$folder")
}

# The link speaks the firmware's types and the rig's transports, never a scenario's.
check host/link rig/ proto/ dut_fw/ host/dut/hil_messages.h
# Resolving a spec is quick: the calibration jigs and field-map tabulation belong to host/setup.
forbid host/scenario fixtures/calibration/ host/setup/
# An emulated run reaches no transport, and the runner knows no command line.
forbid host/runner host/cli/ host/cache/ host/fidelity/ host/pipeline/ host/work_precision/ \
  host/setup/ host/link/ host/dut/process_dut.h host/dut/serial_dut.h \
  rig/udp_bus.h rig/socketcan_bus.h rig/gs_usb rig/libusb rig/can_open.h
# The checks read envelopes resolved from the spec, never the spec's messages.
forbid host/checks proto/scenario.pb.h
# A report is written from a run's results; it runs nothing.
forbid host/report host/runner/ host/fidelity/ host/pipeline/ host/cli/
# The run pipeline is a library under the command line, never the other way round.
forbid host/pipeline host/cli/ host/work_precision/ host/sweep/
# A sweep runs cases through the pipeline; starting shard processes is the command line's.
forbid host/sweep host/cli/
# A comparison reads two results' files; it runs nothing.
forbid host/compare host/cli/ host/runner/ host/pipeline/ host/sweep/ host/fidelity/ host/dut/
# The DUT process is the firmware behind the link on a bus: none of the harness's command line.
forbid dut_emu host/cli/ host/runner/ host/scenario/
# The firmware builds for the target: its own headers, the protocols' numbers, nothing else.
check dut_fw protocol/ proto/hil_link_tags.h
check protocol

# Fewer includes than a floor means the folders moved and the rules check nothing.
readonly min_checked=100
((checked >= min_checked)) || {
  echo "FAIL: only $checked includes checked (at least $min_checked expected)"
  failures=$((failures + 1))
}
((failures == 0)) || exit 1
echo "layering: $checked includes checked"
