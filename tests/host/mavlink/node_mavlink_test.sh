#!/usr/bin/env bash
# The MAVLink codec (host/mavlink/) against node-mavlink, an implementation generated from the same
# message definitions by other people (tests/host/mavlink/node_mavlink_check.mjs): every message
# the codec knows, written by each and read by the other, field by field. node-mavlink comes from
# the npm registry into a cache outside the repository (HILRIG_NODE_CACHE, by default
# ~/.cache/hilrig/node-mavlink-VERSION), once; nothing of it is kept in the tree. With BIN_DIR, it
# also flies hover and load_ramp through PX4's stand-in (`hilrig run --dut mavlink-emu`) and reads
# each run's mavlink.tlog with node-mavlink.
# Skips (77) without node or npm, or when npm cannot reach the registry.
# Usage: node_mavlink_test.sh SOURCE_DIR MAVLINK_VECTORS [BIN_DIR]
set -euo pipefail
source_dir=$1
vectors=$2
bin_dir=${3:-}
readonly version=2.3.0

# shellcheck source=../../support/npm_cache.sh
source "$source_dir/tests/support/npm_cache.sh"
cache=${HILRIG_NODE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hilrig/node-mavlink-$version}
status=0
npm_cache_install "$cache" "node-mavlink@$version" || status=$?
((status == 0)) || exit "$status"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run_tlogs=()
if [[ -n $bin_dir ]]; then
  for scene in hover load_ramp; do
    if ! "$bin_dir/hilrig" run "$source_dir/scenarios/$scene.textproto" --no-reference \
      --dut mavlink-emu --out "$work/$scene" >"$work/$scene.log" 2>&1; then
      echo "FAIL: $scene over --dut mavlink-emu did not pass:" >&2
      cat "$work/$scene.log" >&2
      exit 1
    fi
    run_tlogs+=("$scene=$work/$scene/mavlink.tlog")
  done
fi
node "$source_dir/tests/host/mavlink/node_mavlink_check.mjs" "$cache" "$vectors" "$work" \
  "${run_tlogs[@]}"
