#!/usr/bin/env bash
# Boots the STM32F405 bench image on QEMU's netduinoplus2 with -icount (SysTick then counts virtual
# time, so the figures repeat run to run) and checks its sign of life on USART1: the banner, a
# bench line with the controller armed and the tactile front end ready, and a p99 work per
# control step inside the 1 ms period. Skips (77) without qemu-system-arm or the arm-none-eabi
# cross compiler.
# Usage: qemu_boot_test.sh SOURCE_DIR
set -euo pipefail

source_dir=$1
source "$(dirname "$0")/target_image.sh"
require_tools qemu-system-arm arm-none-eabi-g++

work_dir=$(mktemp -d)
qemu_pid=
cleanup() {
  [[ -n $qemu_pid ]] && kill "$qemu_pid" 2>/dev/null || true
  rm -rf "$work_dir"
}
trap cleanup EXIT
target_images "$source_dir" "$work_dir/build"
image=$image_dir/dut_fw_bench_stm32f405.elf
usart1=$work_dir/usart1.log
coproc qemu {
  exec qemu-system-arm -M netduinoplus2 -display none -monitor none -icount shift=0 \
    -kernel "$image" -serial stdio -serial null </dev/null 2>"$work_dir/qemu.log"
}
qemu_pid=$qemu_PID

# Reads USART1 line by line until the echo prompt; the timeout only bounds a hung boot (the bench
# takes well under a second of host time).
while IFS= read -r -t 20 line <&"${qemu[0]}"; do
  printf '%s\n' "${line%$'\r'}" >>"$usart1"
  [[ $line == echo:* ]] && break
done
grep -q '^echo:' "$usart1" 2>/dev/null || {
  echo "FAIL: no sign of life on USART1 within 20 s"
  cat "$work_dir/qemu.log"
  exit 1
}

cat "$usart1"
grep -q '^hilrig dut_fw stm32f405: clock ' "$usart1" || { echo "FAIL: no banner"; exit 1; }
bench=$(grep '^bench: ' "$usart1") || { echo "FAIL: no bench line"; exit 1; }
field() { sed -n "s/.* $1 \([0-9]*\).*/\1/p" <<<"$bench"; }
[[ $(field armed) == 1 ]] || { echo "FAIL: controller not armed"; exit 1; }
[[ $(field tactile_ready) == 1 ]] || { echo "FAIL: tactile front end not ready"; exit 1; }
cycles_per_period=$((168000000 / 1000))
p99=$(field p99)
((p99 > 0 && p99 < cycles_per_period)) || { echo "FAIL: p99 $p99 cycles/step"; exit 1; }
echo "qemu boot: p99 $p99 of $cycles_per_period cycles per control period"
