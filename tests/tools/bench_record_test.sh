#!/usr/bin/env bash
# scripts/bench-record writes a record of one commit that scripts/bench-compare reads: the same
# record compares as the same, more instructions per tick or a lost benchmark read as slower, wall
# times from another machine are not graded, and a damaged or foreign file cannot be compared.
# Usage: bench_record_test.sh SOURCE_DIR BUILD_DIR. Skips (77) without valgrind.
set -uo pipefail
source_dir=$1
build_dir=$2
command -v valgrind >/dev/null || { echo "valgrind not installed"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

record_cmd=("$source_dir/scripts/bench-record" --build "$build_dir" --out "$work/records"
  --filter 'BM_CandumpLine|BM_SignificantDecimal' --repetitions 2 --min-time 0.01 --scenes hover)
"${record_cmd[@]}" >"$work/record.out" 2>"$work/record.err" || {
  cat "$work/record.err"
  fail "bench-record exited $?"
  exit 1
}
record=$(tail -1 "$work/record.out")
[[ -f $record && $record == "$work/records/"*.json ]] || fail "no record at '$record'"

# What the record holds: both benchmarks with a median, and hover's 40 000 ticks counted.
python3 - "$record" <<'PY' || fail "record content"
import json, sys
record = json.load(open(sys.argv[1]))
names = {b["name"] for b in record["benchmark"]["benchmarks"]}
assert {"BM_CandumpLine_median", "BM_SignificantDecimal_median"} <= names, names
[hover] = record["instructions"]
assert hover["scene"] == "hover" and hover["ticks"] == 40000, hover
assert 500 < hover["instructions_per_tick"] < 100000, hover
assert record["commit"] and record["machine"]["num_cpus"] >= 1, record["machine"]
PY

# Writes a changed copy of the record: `edit` is Python run on the parsed record `r`.
variant() {
  python3 - "$record" "$work/$1.json" "$2" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(r, open(sys.argv[2], "w"))
PY
}
compare() {
  "$source_dir/scripts/bench-compare" "$@" >"$work/compare.out" 2>&1
  echo $?
}
expect() {  # expect CODE PATTERN ARGS...: the exit code and a line of the output
  local code=$1 pattern=$2
  shift 2
  local got
  got=$(compare "$@")
  [[ $got == "$code" ]] || fail "bench-compare $* exited $got, not $code: $(cat "$work/compare.out")"
  grep -Eq -- "$pattern" "$work/compare.out" ||
    fail "bench-compare $*: no line matching '$pattern' in: $(cat "$work/compare.out")"
}

expect 0 '^SAME +instructions_per_tick +hover ' "$record" "$record"
variant more 'r["instructions"][0]["instructions_per_tick"] *= 1.02'
expect 1 '^SLOWER +instructions_per_tick +hover .*\+2\.0%' "$record" "$work/more.json"
expect 0 '^SAME +instructions_per_tick' "$record" "$work/more.json" --instructions-tolerance 0.05
expect 0 '^FASTER +instructions_per_tick +hover ' "$work/more.json" "$record"
variant gone 'r["benchmark"]["benchmarks"] = [b for b in r["benchmark"]["benchmarks"]
  if b["run_name"] != "BM_SignificantDecimal"]'
expect 1 '^GONE +time_ns +BM_SignificantDecimal' "$record" "$work/gone.json"
expect 0 '^NEW +time_ns +BM_SignificantDecimal' "$work/gone.json" "$record"
variant slow 'for b in r["benchmark"]["benchmarks"]: b["real_time"] *= 3'
expect 1 '^SLOWER +time_ns +BM_CandumpLine ' "$record" "$work/slow.json"
variant elsewhere 'r["machine"]["host_name"] = "another"
for b in r["benchmark"]["benchmarks"]: b["real_time"] *= 3'
expect 0 '^UNGRADED +time_ns +BM_CandumpLine ' "$record" "$work/elsewhere.json"
variant disjoint 'r["benchmark"]["benchmarks"] = []; r["instructions"] = []'
expect 2 'nothing|no benchmark or scene in common' "$record" "$work/disjoint.json"
head -c 200 "$record" >"$work/cut.json"
expect 2 'cut.json: not JSON' "$record" "$work/cut.json"
echo '{"benchmarks": []}' >"$work/foreign.json"
expect 2 'foreign.json: not a record' "$work/foreign.json" "$record"
expect 2 'missing.json' "$record" "$work/missing.json"

"$source_dir/scripts/bench-record" --build "$build_dir" --out "$work/records" --scenes nosuch \
  >"$work/bad.out" 2>&1
[[ $? == 2 ]] && grep -q 'no scenario scenarios/nosuch.textproto' "$work/bad.out" ||
  fail "an unknown scene: $(cat "$work/bad.out")"

((failures == 0)) && echo "bench record: all checks passed"
exit $((failures > 0))
