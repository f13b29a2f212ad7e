#!/usr/bin/env bash
# Checks that each folder includes only what its library may depend on (docs/libraries.md), in
# two ways. Every folder that holds C++ has a level below (a folder the table does not place
# fails), and a quoted #include may only reach a folder of a lower level, or the folder itself: no
# include goes up or sideways, so the folders form layers and no two include each other. Then the
# finer rules: a quoted #include of a folder outside the allowed list, or of a forbidden prefix,
# fails with the file and the rule. Rules are prefixes of repository paths.
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

# forbid FOLDER PREFIX... [-- EXCEPT...]: no quoted include starts with one of the prefixes,
# unless it is one of the exceptions (whole paths).
forbid() {
  local folder=$1
  shift
  local prefixes=() exceptions=()
  while (($# > 0)) && [[ $1 != -- ]]; do
    prefixes+=("$1")
    shift
  done
  (($# > 0)) && shift && exceptions=("$@")
  local file target prefix exception excepted
  while read -r file target; do
    checked=$((checked + 1))
    excepted=0
    for exception in "${exceptions[@]}"; do
      [[ $target == "$exception" ]] && excepted=1
    done
    ((excepted)) && continue
    for prefix in "${prefixes[@]}"; do
      if [[ $target == "$prefix"* ]]; then
        echo "FAIL: $file includes $target; $folder/ must not include $prefix"
        failures=$((failures + 1))
      fi
    done
  done < <(includes "$folder")
}

# The layers, lowest first. proto/ is generated headers (the schemas and the link's field
# numbers), proto/foxglove/ those of the Foxglove schemas run.mcap carries; tests/support/ is the
# test helpers; every other folder under tests/, and bench/ and fuzz/, sit on top of everything
# they exercise.
declare -A level=(
  [protocol]=0 [proto]=0 [proto/foxglove]=0
  [rig]=1 [dut_link]=1 [host/mavlink]=1
  [dut_fw]=2 [dut_link/posix]=2
  [dut_fw/target]=3 [examples/hover_dut]=3 [host/plant]=3 [host/trace]=3 [host/link]=3 [host/mcap]=3
  [host/sensors]=4 [fixtures/objects]=4 [host/checks]=4
  [host/sensors/tactile]=5 [host/report]=5
  [fixtures/calibration]=6 [host/compare]=6 [host/scenario]=6
  [host/dut]=7 [host/setup]=7
  [host/cache]=8 [host/runner]=8 [dut_emu]=8 [host/linked_dut]=8
  [host/fidelity]=9 [host/replay]=9
  [host/pipeline]=10
  [host/sweep]=11 [host/work_precision]=11
  [host/cli]=12
  [tests/support]=90
  [bench]=91 [fuzz]=91
)
level_of() {
  if [[ -n ${level[$1]+set} ]]; then
    echo "${level[$1]}"
  elif [[ $1 == tests/* ]]; then
    echo 91
  fi
}

while IFS= read -r folder; do
  own=$(level_of "$folder")
  if [[ -z $own ]]; then
    echo "FAIL: $folder/ holds C++ but has no level in tests/tools/layering_test.sh"
    failures=$((failures + 1))
    continue
  fi
  while read -r file target; do
    checked=$((checked + 1))
    target_folder=$(dirname "$target")
    [[ $target_folder == "$folder" ]] && continue
    theirs=$(level_of "$target_folder")
    if [[ -z $theirs ]]; then
      echo "FAIL: $file includes $target, in $target_folder/, which has no level"
      failures=$((failures + 1))
    elif ((theirs >= own)); then
      echo "FAIL: $file includes $target: $target_folder/ (level $theirs) is not below" \
        "$folder/ (level $own)"
      failures=$((failures + 1))
    fi
  done < <(includes "$folder")
done < <(find . \( -name .git -o -exec test -f '{}/CMakeCache.txt' \; \) -prune -o \
  -type f \( -name '*.h' -o -name '*.cc' \) -printf '%h\n' | sed 's|^\./||' | sort -u)

# The link speaks the firmware's types, MAVLink and the rig's transports, never a scenario's.
check host/link rig/ proto/ dut_fw/ dut_link/ host/mavlink/
# Resolving a spec is quick: the calibration jigs and field-map tabulation belong to host/setup.
forbid host/scenario fixtures/calibration/ host/setup/
# An emulated run reaches no transport, and the runner knows no command line; of the link it
# takes only the message structs the DUT seam speaks.
forbid host/runner host/cli/ host/cache/ host/fidelity/ host/pipeline/ host/work_precision/ \
  host/setup/ host/link/ host/linked_dut/ \
  rig/udp_bus.h rig/socketcan_bus.h rig/gs_usb rig/libusb rig/can_open.h \
  -- host/link/hil_messages.h
# The checks read envelopes resolved from the spec, never the spec's messages.
forbid host/checks proto/scenario.pb.h
# A report is written from a run's results; it runs nothing.
forbid host/report host/runner/ host/fidelity/ host/pipeline/ host/cli/
# The run pipeline is a library under the command line, never the other way round.
forbid host/pipeline host/cli/ host/work_precision/ host/sweep/
# A sweep runs cases through the pipeline; starting shard processes is the command line's.
forbid host/sweep host/cli/
# A comparison reads two results' files; it runs nothing.
forbid host/compare host/cli/ host/runner/ host/pipeline/ host/sweep/ host/fidelity/ host/dut/ \
  host/linked_dut/
# The DUT process is the firmware behind the link on a bus: none of the harness's command line.
forbid dut_emu host/cli/ host/runner/ host/scenario/
# The firmware builds for the target: its own headers, the link library, the protocols' numbers,
# nothing else. The link library is for any controller: the protocols and nothing of dut_fw's.
check dut_fw dut_link/ protocol/ proto/hil_link_tags.h
check dut_link protocol/ proto/hil_link_tags.h
check dut_link/posix dut_link/
# An MCAP file is bytes: the rig's result type and nothing of a run (a protobuf channel takes the
# message's descriptor, never the rig's .proto files).
check host/mcap rig/result.h rig/check.h
# The MAVLink codec is the standard library only: a tool or a DUT may take it alone.
check host/mavlink
# A team's own DUT takes the link library, never the rig's controller.
check examples/hover_dut dut_link/
check protocol

# Fewer includes than a floor means the folders moved and the rules check nothing.
readonly min_checked=1000
((checked >= min_checked)) || {
  echo "FAIL: only $checked includes checked (at least $min_checked expected)"
  failures=$((failures + 1))
}
((failures == 0)) || exit 1
echo "layering: $checked includes checked"
