#!/usr/bin/env bash
# usb-e2e (docs/usb.md): the USB link end to end as the Linux guest of the USB test sees it — Debian's
# kernel under QEMU (TCG), xHCI, usbredir, hmp-usb-sim (the core and our USB stack natively) — measured by
# tools/bench/usb_e2e_guest.cpp on /dev/hidraw0 in the guest: report round trip (Sync written → SyncReply
# read) median and p99 over 2,000, and notes per second sustained for 5 s under the credit rule with the
# device's counters (every note started, none rejected). Goals: p99 ≤ 3 ms, ≥ 4,500 notes/s, no loss.
# Note: the guest runs emulated (no KVM), so its own overhead is in every figure.
# Run by scripts/bench with the host build directory as $1.
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target hmp-usb-sim bench_usb_e2e_guest >&2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tests/usb/run-guest.sh "$build/bin" "$build/usb-guest-cache" tests/usb/guest_bench.sh "$tmp/console" \
  "$build/bench/bench_usb_e2e_guest" >&2 || { cat "$tmp/console" >&2; exit 1; }
line=$(grep -a -o 'usb-e2e rtt_median_us=.*' "$tmp/console") || { cat "$tmp/console" "$tmp/console.rig" >&2; exit 1; }
field() { tr ' ' '\n' <<<"$line" | sed -n "s/^$1=//p" | tr -d '\r'; }
p='"params":{"guest":"linux-6.1 tcg","path":"hidraw-xhci-usbredir"}'
printf '{"bench":"usb-e2e","metric":"round_trip_median","value":%s,"unit":"us",%s}\n' "$(field rtt_median_us)" "$p"
printf '{"bench":"usb-e2e","metric":"round_trip_p99","value":%s,"unit":"us",%s}\n' "$(field rtt_p99_us)" "$p"
printf '{"bench":"usb-e2e","metric":"notes_per_second","value":%s,"unit":"notes/s",%s}\n' "$(field notes_per_s)" "$p"
for k in sent started rejected late; do
  printf '{"bench":"usb-e2e","metric":"notes_%s","value":%s,"unit":"notes",%s}\n' "$k" "$(field $k)" "$p"
done
