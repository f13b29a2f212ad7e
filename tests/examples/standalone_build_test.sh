#!/usr/bin/env bash
# A team builds its DUT outside the rig's tree: the example, copied with the DUT-side library
# (dut_link/), the tactile protocol (protocol/) and the generated field numbers
# (proto/hil_link_tags.h) and nothing else, compiles with the plain compiler and runs. Any include
# of the rig's own code (dut_fw/, rig/, host/) or a library beyond the C++ standard one fails here.
# Usage: standalone_build_test.sh SOURCE_DIR BUILD_DIR
set -euo pipefail

source_dir=$1
build_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/examples" "$work/proto"
cp -r "$source_dir/dut_link" "$source_dir/protocol" "$work/"
cp -r "$source_dir/examples/hover_dut" "$work/examples/"
cp "$build_dir/generated/proto/hil_link_tags.h" "$work/proto/"
cd "$work"
c++ -std=c++20 -O2 -Wall -Wextra -Werror -I. examples/hover_dut/main.cc dut_link/posix/line_io.cc \
  -o hover_dut
status=0
./hover_dut --bogus >usage.txt 2>&1 || status=$?
if ((status != 2)) || ! grep -q "usage: hover_dut" usage.txt; then
  echo "FAIL: the standalone hover_dut did not print its usage and exit 2 (exit $status)"
  cat usage.txt
  exit 1
fi
echo "ok: hover_dut builds from dut_link/, protocol/ and proto/hil_link_tags.h alone"
