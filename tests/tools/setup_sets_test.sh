#!/usr/bin/env bash
# scripts/setup's two sets: `run` (what ./scripts/run needs) holds none of the tools only the tests
# drive (Slurm, munge, Chromium, clang-format, valgrind, the vm test's QEMU), and `test` holds
# every package of `run` and those. Reads the sets with --list, which installs nothing.
# Usage: setup_sets_test.sh SOURCE_DIR
set -euo pipefail
setup=$1/scripts/setup
failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

run_set=$(bash "$setup" run --list) || fail "setup run --list exited $?"
test_set=$(bash "$setup" test --list) || fail "setup test --list exited $?"
[[ -n $run_set ]] || fail "setup run --list printed nothing"

for tool in slurm-wlm munge chromium clang-format valgrind qemu-system-x86 python3-can; do
  grep -qx "$tool" <<<"$run_set" && fail "the run set installs $tool, which only the tests use"
  grep -qx "$tool" <<<"$test_set" || fail "the test set lacks $tool"
done
for needed in cmake g++ libprotobuf-dev qemu-system-arm gcc-arm-none-eabi; do
  grep -qx "$needed" <<<"$run_set" || fail "the run set lacks $needed"
done
while IFS= read -r package; do
  grep -qx "$package" <<<"$test_set" || fail "the test set lacks $package of the run set"
done <<<"$run_set"

status=0
bash "$setup" run --bogus >/dev/null 2>&1 || status=$?
((status == 2)) || fail "an unknown option exited $status, not 2"

((failures == 0)) || exit 1
echo "PASS: setup run lists $(wc -l <<<"$run_set") packages, setup test $(wc -l <<<"$test_set")"
