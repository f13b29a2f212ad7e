#!/usr/bin/env bash
# The real-kernel test of the SocketCAN backend. This machine's kernel (and CI's) has no AF_CAN, so
# the test boots Debian's own kernel under QEMU (TCG: no KVM here), loads can, can-raw, can-dev and
# vcan from that kernel's package, creates vcan0 (and vcan1 with a classic MTU), and runs inside:
#   1. socketcan_vm_tests: tests/rig/socketcan_bus_test.cc (SocketCAN tests and the shared CanBus
#      conformance suite) on vcan0;
#   2. vcan_exchange: seven emulated sensor nodes and a DUT exchanging frames over vcan0, printed
#      in candump form, with can-utils' candump listening alongside when it is installed;
#   3. hilrig run SCENARIO --dut process --can socketcan:vcan0 --realtime: the emulated sensor
#      nodes' frames cross vcan0 to the dut_emu process, which must consume some of them.
# The guest prints HILRIG_VM_RESULT=PASS or =FAIL and powers off; this script greps the console.
#
# Where the kernel comes from: `apt-get download` of the package linux-image-amd64 depends on, and
# only vmlinuz plus the four CAN modules extracted with dpkg-deb into a cache
# ($HILRIG_VM_CACHE, default ~/.cache/hilrig-vm), so nothing is installed, no boot hooks run, and
# later runs reuse it. HILRIG_VM_KERNEL_DIR can point at a tree with boot/vmlinuz-* and
# lib/modules/<version>/ instead (e.g. / on a Debian host that has linux-image-amd64 installed).
#
# Exit codes: 0 pass, 1 fail, 77 skip (no QEMU, no busybox, no iproute2 or no kernel package),
# which ctest reports as skipped. A hard timeout ($HILRIG_VM_TIMEOUT_S, default 240 s) kills QEMU,
# so the test can never hang CI.
#
# Usage: run_vm_test.sh WORK_DIR SOCKETCAN_TESTS_BINARY VCAN_EXCHANGE_BINARY HILRIG DUT_EMU SCENARIO
set -euo pipefail

work_dir=$1
tests_binary=$2
vcan_exchange=$3
hilrig=$4
dut_emu=$5
scenario=$6
timeout_s=${HILRIG_VM_TIMEOUT_S:-240}
cache_dir=${HILRIG_VM_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/hilrig-vm}

skip() {
  echo "SKIP: $*"
  exit 77
}
fail() {
  echo "FAIL: $*"
  exit 1
}
log() { echo "vm_test: $*"; }

start_s=$SECONDS
command -v qemu-system-x86_64 >/dev/null ||
  skip "qemu-system-x86_64 not found (Debian package qemu-system-x86; scripts/setup installs it)"
busybox=$(command -v busybox || true)
[[ -n $busybox ]] || skip "busybox not found (Debian package busybox-static)"
ip_tool=$(PATH=$PATH:/usr/sbin:/sbin command -v ip || true)
[[ -n $ip_tool ]] || skip "ip not found (Debian package iproute2: it creates the vcan interfaces)"
for binary in "$tests_binary" "$vcan_exchange" "$hilrig" "$dut_emu"; do
  [[ -x $binary ]] || fail "binary missing: $binary"
done

# ---- (a) the kernel and its CAN modules ----
can_modules=(
  kernel/net/can/can.ko
  kernel/net/can/can-raw.ko
  kernel/drivers/net/can/dev/can-dev.ko  # vcan needs it loaded first
  kernel/drivers/net/can/vcan.ko
)

# Sets kernel_tree to the tree (with boot/ and lib/modules/) to use, downloading it if needed.
# Not run in a subshell, so that its skip and fail end the script with their message.
find_kernel_tree() {
  if [[ -n ${HILRIG_VM_KERNEL_DIR:-} ]]; then
    kernel_tree=$HILRIG_VM_KERNEL_DIR
    return
  fi
  local package
  package=$(apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*\)$/\1/p' | head -n1)
  [[ -n $package ]] ||
    skip "cannot resolve linux-image-amd64 to a kernel package (run apt-get update?)"
  local tree=$cache_dir/$package
  if [[ ! -f $tree/complete ]]; then
    mkdir -p "$cache_dir"
    # One download at a time, should two builds run this test at once.
    exec 9>"$cache_dir/lock"
    flock 9
    if [[ ! -f $tree/complete ]]; then
      log "fetching $package (once; cached in $cache_dir)"
      local download=$cache_dir/download
      rm -rf "$download" "$tree"
      mkdir -p "$download" "$tree"
      (cd "$download" && apt-get download "$package" >/dev/null 2>&1) ||
        skip "apt-get download $package failed (no network or no apt lists)"
      # Only vmlinuz and the CAN modules: the full package unpacks to ~400 MB.
      dpkg-deb --fsys-tarfile "$download"/*.deb |
        tar -x -C "$tree" --wildcards './boot/vmlinuz-*' './lib/modules/*/kernel/net/can/*' \
          './lib/modules/*/kernel/drivers/net/can/vcan.ko' \
          './lib/modules/*/kernel/drivers/net/can/dev/can-dev.ko' ||
        fail "could not extract $package"
      rm -rf "$download"
      touch "$tree/complete"
    fi
    exec 9>&-
  fi
  kernel_tree=$tree
}

find_kernel_tree
kernels=("$kernel_tree"/boot/vmlinuz-*)
kernel=${kernels[0]}
[[ -f $kernel ]] || skip "no boot/vmlinuz-* in $kernel_tree"
kernel_version=${kernel##*/vmlinuz-}
module_dir=$kernel_tree/lib/modules/$kernel_version
for module in "${can_modules[@]}"; do
  [[ -f $module_dir/$module || -f $module_dir/$module.xz ]] ||
    skip "kernel $kernel_version lacks $module"
done
log "kernel $kernel_version from $kernel_tree"

# ---- (b) the initramfs ----
root=$work_dir/initramfs
rm -rf "$root"
mkdir -p "$root"/{bin,dev,proc,sys,tmp,modules}

# Copies an executable and every shared library it loads, at the same paths, so it runs in the
# guest exactly as on the host.
copy_with_libs() {
  local binary=$1 target=$2
  cp "$binary" "$root/$target"
  local lib
  for lib in $(ldd "$binary" 2>/dev/null | grep -o '/[^ ]*' || true); do
    [[ -e $root$lib ]] && continue
    mkdir -p "$root$(dirname "$lib")"
    cp -L "$lib" "$root$lib"
  done
}

copy_with_libs "$busybox" bin/busybox
# Outside /bin, where busybox --install would shadow it with its own ip (no vcan support there).
mkdir -p "$root/usr/sbin"
copy_with_libs "$ip_tool" usr/sbin/ip
copy_with_libs "$tests_binary" bin/socketcan_vm_tests
copy_with_libs "$vcan_exchange" bin/vcan_exchange
copy_with_libs "$hilrig" bin/hilrig
copy_with_libs "$dut_emu" bin/dut_emu  # next to hilrig, where it looks for it
mkdir -p "$root/scenarios"
cp "$scenario" "$root/scenarios/bench.textproto"
candump=$(command -v candump || true)
[[ -n $candump ]] && copy_with_libs "$candump" bin/candump
for module in "${can_modules[@]}"; do
  name=$(basename "$module")
  if [[ -f $module_dir/$module ]]; then
    cp "$module_dir/$module" "$root/modules/$name"
  else
    xz -dc "$module_dir/$module.xz" >"$root/modules/$name"  # busybox insmod takes plain .ko
  fi
done

cat >"$root/init" <<'INIT'
#!/bin/busybox sh
# Runs as PID 1 in the guest. Every path ends in the result marker and a power-off.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
echo "hilrig-vm: guest kernel $(uname -r)"

finish() {
  echo "HILRIG_VM_RESULT=$1"
  poweroff -f
}

for module in can can-raw can-dev vcan; do
  insmod /modules/$module.ko || { echo "hilrig-vm: insmod $module failed"; finish FAIL; }
done
ip=/usr/sbin/ip  # iproute2's: it knows `type vcan`
$ip link add dev vcan0 type vcan && $ip link set up vcan0 &&
  $ip link add dev vcan1 type vcan && $ip link set vcan1 mtu 16 && $ip link set up vcan1 ||
  { echo "hilrig-vm: could not create vcan0/vcan1"; finish FAIL; }
$ip -details link show vcan0
$ip -details link show vcan1

status=PASS
echo "hilrig-vm: ---- socketcan_vm_tests ----"
HILRIG_SOCKETCAN_IFACE=vcan0 HILRIG_SOCKETCAN_CLASSIC_IFACE=vcan1 \
  /bin/socketcan_vm_tests --gtest_color=no || status=FAIL

# 10 rounds: 70 sample frames and 10 DUT commands. can-utils' candump listens independently and
# stops after those 80 frames (or 5 s of silence), so its log flushes whole.
rounds=10
if [ -x /bin/candump ]; then
  candump -L -n $((rounds * 8)) -T 5000 vcan0 >/tmp/candump.log 2>&1 &
  candump_pid=$!
fi
echo "hilrig-vm: ---- vcan_exchange ----"
/bin/vcan_exchange vcan0 $rounds || status=FAIL
if [ -n "${candump_pid:-}" ]; then
  wait $candump_pid
  echo "hilrig-vm: can-utils candump saw $(grep -c vcan0 /tmp/candump.log) frames on vcan0:"
  head -n 9 /tmp/candump.log
  echo "..."
fi

# The HIL link is TCP on loopback. Under TCG the real-time loop runs late, so its verdicts are not
# graded here: only that the frames crossed vcan0 and the DUT process consumed them.
echo "hilrig-vm: ---- hilrig run --dut process --can socketcan:vcan0 ----"
$ip link set up lo
/bin/hilrig run /scenarios/bench.textproto --dut process --can socketcan:vcan0 --realtime \
  --rt-priority 0 --out /tmp/run --reference-cache /tmp/cache
echo "hilrig-vm: hilrig run exited $?"
grep '"fidelity": "dut_fw' /tmp/run/report.json
consumed=$(sed -n '/"stream": "can"/{n;s/[^0-9]//g;p}' /tmp/run/report.json)
echo "hilrig-vm: the dut process consumed ${consumed:-0} CAN frames over vcan0"
[ "${consumed:-0}" -gt 0 ] || status=FAIL
finish $status
INIT
chmod +x "$root/init"

initrd=$work_dir/initramfs.cpio
if command -v cpio >/dev/null; then
  (cd "$root" && find . | cpio -o -H newc --quiet >"$initrd")
else
  (cd "$root" && find . | "$busybox" cpio -o -H newc >"$initrd")
fi
log "initramfs $(du -h "$initrd" | cut -f1) built in $((SECONDS - start_s)) s"

# ---- (c) boot, (e) grade ----
console=$work_dir/console.log
log "booting under qemu-system-x86_64 -accel tcg (timeout ${timeout_s} s)"
boot_s=$SECONDS
set +e
timeout --kill-after=10 "$timeout_s" qemu-system-x86_64 \
  -accel tcg -m 512 -smp 1 -nographic -no-reboot -nic none -monitor none \
  -kernel "$kernel" -initrd "$initrd" \
  -append "console=ttyS0 panic=-1 loglevel=4 edd=off rdinit=/init" </dev/null 2>&1 |
  tr -d '\r' | tee "$console"
qemu_status=${PIPESTATUS[0]}
set -e
log "guest ran for $((SECONDS - boot_s)) s (qemu exit $qemu_status); console log: $console"

if grep -q '^HILRIG_VM_RESULT=PASS' "$console"; then
  # Belt and braces: the guest's PASS must come with tests that really ran on vcan0.
  grep -q '\[  PASSED  \]' "$console" || fail "no gtest PASSED line in the console"
  # A SocketCanTest that skips inside the VM could not open vcan0: that is a failure here.
  if grep -q '^\[  SKIPPED \] SocketCan\(Test\.\|/\)' "$console"; then
    fail "SocketCAN tests skipped inside the VM"
  fi
  grep -q '^vcan_exchange: .* 0 mismatches' "$console" || fail "no vcan_exchange summary"
  grep -q 'CAN frames over socketcan:vcan0' "$console" || fail "the run's report names no vcan0"
  grep -q '^hilrig-vm: the dut process consumed [1-9][0-9]* CAN frames' "$console" ||
    fail "no CAN frame crossed vcan0 to the dut process"
  echo "PASS: SocketCAN backend on kernel $kernel_version (vcan) in $((SECONDS - start_s)) s"
  exit 0
fi
if grep -q '^HILRIG_VM_RESULT=FAIL' "$console"; then
  fail "the guest reported a failure (see above)"
fi
if ((qemu_status == 124 || qemu_status == 137)); then
  fail "timed out after ${timeout_s} s without a result"
fi
fail "the guest stopped without a result marker (qemu exit $qemu_status)"
