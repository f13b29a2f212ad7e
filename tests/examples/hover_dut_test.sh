#!/usr/bin/env bash
# The example DUT (examples/hover_dut: a controller of its own on the DUT-side link library, none
# of dut_fw's) flies the hover scene through each way a team's DUT reaches the rig, and every
# envelope passes: `--dut exec:` (the rig starts it), `--dut listen:` (it is started by hand and
# dials in with the token file), and a serial line (two pseudo-terminal pairs joined by
# pty_null_modem, `--dut serial:` on one side, `hover_dut --serial` on the other). A DUT that dials
# in with another run's token is refused and the run fails, naming the token; started on the
# process link by mistake, it says which link it speaks.
# Usage: hover_dut_test.sh SOURCE_DIR BIN_DIR
set -euo pipefail

source_dir=$1
bin=$2
spec=$source_dir/scenarios/hover.textproto
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
cd "$work"
failures=0

# expect_pass NAME: the run NAME wrote a report and every envelope passed.
expect_pass() {
  local name=$1
  if ! grep -q '"passed": *true' "$name/report.json" 2>/dev/null; then
    echo "FAIL: $name: the hover scene did not pass"
    cat "$name.log"
    failures=$((failures + 1))
  elif grep -q "^FAIL\|NOT EVALUATED" "$name.log"; then
    echo "FAIL: $name: an envelope failed or was not evaluated"
    failures=$((failures + 1))
  else
    echo "ok: $name"
  fi
}

# wait_for FILE TEXT: until FILE holds TEXT, at most 20 s.
wait_for() {
  for _ in $(seq 200); do
    grep -q "$2" "$1" 2>/dev/null && return 0
    sleep 0.1
  done
  echo "FAIL: $1 never said \"$2\""
  cat "$1" || true
  return 1
}

# The rig starts the program.
"$bin/hilrig" run "$spec" --dut "exec:$bin/hover_dut" --dut-link line --out exec >exec.log 2>&1 ||
  true
expect_pass exec

# Started on the process link by mistake, it says which link it speaks, and the run fails.
status=0
"$bin/hilrig" run "$spec" --dut "exec:$bin/hover_dut" --out wrong_link >wrong_link.log 2>&1 ||
  status=$?
if ((status != 0)) && grep -q "speaks the line link" wrong_link.log; then
  echo "ok: a line-link DUT on the process link is named"
else
  echo "FAIL: hover_dut on the process link: exit $status"
  cat wrong_link.log
  failures=$((failures + 1))
fi

# A person starts it, after the run says where to dial.
"$bin/hilrig" run "$spec" --dut "listen:127.0.0.1:$((20000 + RANDOM % 20000))" --dut-link line --out listen \
  >listen.log 2>&1 &
pids+=($!)
runner=$!
wait_for listen.log "start it with --connect"
endpoint=$(sed -n 's/.*--connect \([^ ]*\) .*/\1/p' listen.log)
"$bin/hover_dut" --connect "$endpoint" --token-file hilrig_link_token >listen_dut.log 2>&1 ||
  { echo "FAIL: hover_dut over listen: exited $?"; failures=$((failures + 1)); }
wait "$runner" || true
expect_pass listen

# Another run's token is refused.
"$bin/hilrig" run "$spec" --dut "listen:127.0.0.1:$((40000 + RANDOM % 20000))" --dut-link line --out wrong \
  --dut-timeout-s 5 >wrong.log 2>&1 &
pids+=($!)
runner=$!
wait_for wrong.log "start it with --connect"
endpoint=$(sed -n 's/.*--connect \([^ ]*\) .*/\1/p' wrong.log)
HILRIG_LINK_TOKEN=00112233445566778899aabbccddeeff "$bin/hover_dut" --connect "$endpoint" \
  >wrong_dut.log 2>&1 || true
status=0
wait "$runner" || status=$?
if ((status == 1)) && grep -q "does not carry this run's link token" wrong.log; then
  echo "ok: another token is refused"
else
  echo "FAIL: a DUT with another token: exit $status"
  cat wrong.log
  failures=$((failures + 1))
fi

# A serial line: pseudo-terminals in place of a board's UARTs.
"$bin/pty_null_modem" >modem.out 2>&1 &
pids+=($!)
wait_for modem.out ready
path() { sed -n "s/^$1 //p" modem.out; }
"$bin/hover_dut" --serial "$(path link_dut),bridge=$(path bridge_dut)" >serial_dut.log 2>&1 &
pids+=($!)
"$bin/hilrig" run "$spec" --dut "serial:$(path link_host),bridge=$(path bridge_host)" \
  --out serial >serial.log 2>&1 || true
expect_pass serial

((failures == 0))
