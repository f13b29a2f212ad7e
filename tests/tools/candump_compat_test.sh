#!/usr/bin/env bash
# Checks that a scenario's can.log is read without error by can-utils' log2asc and python-can's
# LogReader (Debian packages can-utils and python3-can), with the frame count the rig reports.
# Skips (exit 77) when either tool is missing.
set -euo pipefail
hilrig=$1
scenario=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

command -v log2asc >/dev/null || { echo "SKIP: log2asc (can-utils) not installed"; exit 77; }
/usr/bin/python3 -c 'import can' 2>/dev/null || { echo "SKIP: python3-can not installed"; exit 77; }

"$hilrig" run "$scenario" --out "$out" --no-reference >/dev/null
reported=$(sed -n 's/.*"can_frames_logged": "\([0-9]*\)".*/\1/p' "$out/report.json")
[[ -n $reported && $reported -gt 0 ]] || { echo "FAIL: report has no can_frames_logged"; exit 1; }

log2asc -I "$out/can.log" -O "$out/can.asc" can0
asc_frames=$(grep -cE '^ *[0-9]+\.[0-9]+ +[0-9]+ +[0-9A-Fa-f]+x? +Rx' "$out/can.asc" || true)

python_frames=$(/usr/bin/python3 - "$out/can.log" <<'PY'
import sys
import can
print(sum(1 for _ in can.CanutilsLogReader(sys.argv[1])))
PY
)

echo "rig reported $reported frames; log2asc wrote $asc_frames; python-can read $python_frames"
[[ $asc_frames -eq $reported ]] || { echo "FAIL: log2asc frame count differs"; exit 1; }
[[ $python_frames -eq $reported ]] || { echo "FAIL: python-can frame count differs"; exit 1; }
echo "PASS"
