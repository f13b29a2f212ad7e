#!/usr/bin/env bash
# expect_report.sh CANARY MODE PATTERN: runs the canary's bug with the sanitizer options the tests
# run with (ASan's reports sent to a folder of its own, so that scripts/test does not count them);
# passes only when the canary fails and its report matches PATTERN.
set -uo pipefail
canary=$1 mode=$2 pattern=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
ASAN_OPTIONS="${ASAN_OPTIONS:-}:log_path=$dir/report" "$canary" "$mode" >"$dir/output" 2>&1
status=$?
if ((status == 0)); then
  echo "expect_report: $mode exited 0: the sanitizers did not stop it"
  exit 1
fi
if ! grep -q -e "$pattern" "$dir"/*; then
  echo "expect_report: $mode exited $status without a report matching '$pattern':"
  cat "$dir"/*
  exit 1
fi
echo "expect_report: $mode exited $status with: $(grep -h -m1 -e "$pattern" "$dir"/*)"
