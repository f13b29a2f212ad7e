#!/usr/bin/env bash
# Checks that each folder includes only what its library may depend on (the layout table in
# docs/): a quoted #include of a folder outside the allowed list fails with the file, the line and
# the rule. The rules are prefixes of repository paths; a folder's own files are always allowed.
# Usage: layering_test.sh SOURCE_DIR
set -euo pipefail
cd "$1"

failures=0
checked=0

# check FOLDER ALLOWED_PREFIX...: every quoted include in FOLDER/*.{h,cc} (not its subfolders)
# starts with FOLDER/ or one of the prefixes.
check() {
  local folder=$1
  shift
  local file line target allowed ok
  for file in "$folder"/*.h "$folder"/*.cc; do
    [[ -f $file ]] || continue
    while IFS= read -r line; do
      target=${line#*\"}
      target=${target%%\"*}
      checked=$((checked + 1))
      ok=0
      for allowed in "$folder/" "$@"; do
        [[ $target == "$allowed"* ]] && ok=1 && break
      done
      if ((!ok)); then
        echo "FAIL: $file includes $target; $folder/ may include only: $*"
        failures=$((failures + 1))
      fi
    done < <(grep -E '^#include "' "$file" || true)
  done
}

# The link speaks the firmware's types and the rig's transports, never a scenario's.
check host/link rig/ proto/ dut_fw/ host/dut/hil_messages.h

# Fewer includes than a floor means the folders moved and the rules check nothing.
readonly min_checked=20
((checked >= min_checked)) || {
  echo "FAIL: only $checked includes checked (at least $min_checked expected)"
  failures=$((failures + 1))
}
((failures == 0)) || exit 1
echo "layering: $checked includes checked"
