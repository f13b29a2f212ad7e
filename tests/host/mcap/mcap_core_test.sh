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
# A run's own log is read the same way: balloon_grasp's run.mcap (5 s of it), every message decoded.
# Usage: mcap_core_test.sh SOURCE_DIR MCAP_SAMPLE_WRITER HILRIG
set -euo pipefail
source_dir=$1
sample_writer=$2
hilrig=$3
readonly version=2.2.2 fzstd_version=0.1.1 protobufjs_version=7.4.0

for tool in node npm; do
  command -v "$tool" >/dev/null || {
    echo "SKIP: no $tool (./scripts/setup test installs Node.js and npm)"
    exit 77
  }
done
cache=${HILRIG_NODE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/hilrig/mcap-core-$version-protobufjs-$protobufjs_version}
if [[ ! -f $cache/node_modules/@mcap/core/package.json ]]; then
  mkdir -p "$(dirname "$cache")"
  echo "installing @mcap/core $version, fzstd $fzstd_version and protobufjs $protobufjs_version" \
    "into $cache"
  # Into a fresh folder first, so that an interrupted install leaves no half cache behind.
  staging=$(mktemp -d "$cache.XXXXXX")
  if ! npm install --prefix "$staging" --no-save --no-audit --no-fund --loglevel=error \
    "@mcap/core@$version" "fzstd@$fzstd_version" "protobufjs@$protobufjs_version" \
    >"$staging.log" 2>&1; then
    # No network is a machine without the registry, not a defect of the writer.
    if grep -qE 'ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH' \
      "$staging.log"; then
      echo "SKIP: npm cannot reach the registry:"
      cat "$staging.log"
      rm -rf "$staging" "$staging.log"
      exit 77
    fi
    echo "FAIL: npm could not install @mcap/core $version:" >&2
    cat "$staging.log" >&2
    rm -rf "$staging" "$staging.log"
    exit 1
  fi
  rm -rf "$cache" "$staging.log"
  mv "$staging" "$cache"
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$sample_writer" "$work"
status=0
"$hilrig" run "$source_dir/scenarios/balloon_grasp.textproto" --no-reference --duration-s 5 \
  --out "$work/run" >"$work/run.out" 2>&1 || status=$?
((status <= 1)) || { echo "FAIL: hilrig run exited $status"; cat "$work/run.out"; exit 1; }
node "$source_dir/tests/host/mcap/mcap_core_check.mjs" "$cache" "$work/zstd.mcap" \
  "$work/stored.mcap" "$work/run/run.mcap"
