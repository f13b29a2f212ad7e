#!/usr/bin/env bash
# The rig's MCAP writer (host/mcap/) against @mcap/core, the MCAP library Foxglove publishes:
# mcap_sample_writer writes a zstd and a stored file, and tests/host/mcap/mcap_core_check.mjs reads
# each with @mcap/core's indexed reader and checks schemas, channels, every message against the
# Statistics record and the data section's CRC-32, and decodes the protobuf channel with
# protobufjs from the descriptors stored in the file. @mcap/core, fzstd (its zstd decompression in
# Node.js) and protobufjs come from the npm registry into a cache outside the repository
# (HILRIG_NODE_CACHE, by default ~/.cache/hilrig/mcap-core-VERSION-protobufjs-VERSION), once;
# nothing of them is kept in the tree.
# Skips (77) without node or npm, or when npm cannot reach the registry.
# A run's own log is read the same way: balloon_grasp's run.mcap (5 s of it), every message decoded,
# and the Foxglove layout docs/layouts/hilrig.foxglove.json checked against it: every message path
# of its panels names a channel of the log and reaches a value in a decoded message.
# Usage: mcap_core_test.sh SOURCE_DIR MCAP_SAMPLE_WRITER HILRIG
set -euo pipefail
source_dir=$1
sample_writer=$2
hilrig=$3
readonly version=2.2.2 fzstd_version=0.1.1 protobufjs_version=7.4.0

# shellcheck source=../../support/npm_cache.sh
source "$source_dir/tests/support/npm_cache.sh"
cache=${HILRIG_NODE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hilrig/mcap-core-$version-protobufjs-$protobufjs_version}
status=0
npm_cache_install "$cache" "@mcap/core@$version" "fzstd@$fzstd_version" \
  "protobufjs@$protobufjs_version" || status=$?
((status == 0)) || exit "$status"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$sample_writer" "$work"
status=0
"$hilrig" run "$source_dir/scenarios/balloon_grasp.textproto" --no-reference --duration-s 5 \
  --out "$work/run" >"$work/run.out" 2>&1 || status=$?
((status <= 1)) || { echo "FAIL: hilrig run exited $status"; cat "$work/run.out"; exit 1; }
node "$source_dir/tests/host/mcap/mcap_core_check.mjs" "$cache" \
  --layout "$source_dir/docs/layouts/hilrig.foxglove.json" "$work/zstd.mcap" "$work/stored.mcap" \
  "$work/run/run.mcap"
