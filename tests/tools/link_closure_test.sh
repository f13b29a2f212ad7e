#!/usr/bin/env bash
# Checks that libraries and executables hold no CAN transport to a medium outside the process: no
# reference to libusb and no Boost.Asio code among their symbols, and for an executable no libusb
# among its shared libraries. Run on the libraries an emulated run uses, it keeps the transports
# in their own libraries.
# Usage: link_closure_test.sh FILE...   (static libraries or executables)
set -euo pipefail

failures=0
fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
for file in "$@"; do
  [[ -f $file ]] || { fail "$file does not exist"; continue; }
  symbols=$(nm -C "$file" 2>/dev/null) || { fail "nm cannot read $file"; continue; }
  asio=$(grep -c 'boost::asio' <<<"$symbols" || true)
  ((asio == 0)) || fail "$file holds $asio Boost.Asio symbols"
  usb=$(grep -c ' libusb_' <<<"$symbols" || true)
  ((usb == 0)) || fail "$file refers to $usb libusb symbols"
  if [[ -x $file ]] && ldd "$file" | grep -q 'libusb'; then
    fail "$file links libusb"
  fi
done
((failures == 0)) || exit 1
echo "link closure: $# files free of libusb and Boost.Asio"
