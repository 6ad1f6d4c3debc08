#!/usr/bin/env bash
# Test qemu_boot_firmware: boots the firmware image with no host on the UART and the option
# exit-idle-ms=200; it must start, tick at its rate, send its periodic Status (UART frames) and exit 0
# after 200 ms without input, with a summary; the same with link=net over the Ethernet controller (QEMU
# gives the board its LAN9118 with nothing behind it). An unknown option must stop it with exit code 4.
# Usage: check_firmware_boot.sh IMAGE.elf
set -uo pipefail
image=${1:?usage: check_firmware_boot.sh IMAGE.elf}
here=$(dirname "${BASH_SOURCE[0]}")
command -v "${QEMU_SYSTEM_ARM:-qemu-system-arm}" >/dev/null || { echo "FAIL: qemu-system-arm not installed"; exit 1; }
fail() { echo "FAIL: $*"; exit 1; }

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1000 exit-idle-ms=200" </dev/null 2>&1)
code=$?
printf '%s\n' "$out"
[ $code -eq 0 ] || fail "image exited with $code"
grep -q '^HMP qemu-an386 firmware .* tick_hz=1000 trace=off exit_idle_ms=200 listen_after_ms=0 link=uart$' <<<"$out" ||
  fail "banner"
summary=$(grep '^core:' <<<"$out") || fail "no summary"
ticks=$(sed -n 's/.* ticks=\([0-9]*\).*/\1/p' <<<"$summary")
[ "$ticks" = 200 ] || fail "expected 200 ticks before the idle exit, got '$ticks'"
# Idle, the core sends a Status every 100 ticks: two frames went out.
grep -q '^link: .*tx_frames=2 tx_dropped=0' <<<"$out" || fail "expected 2 Status frames on the UART"

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1000 exit-idle-ms=200 link=net" \
  </dev/null 2>&1)
code=$?
printf '%s\n' "$out"
[ $code -eq 0 ] || fail "image with link=net exited with $code"
grep -q '^HMP qemu-an386 firmware .* link=net$' <<<"$out" || fail "banner with link=net"
grep -q '^net: rx_frames=0 rx_foreign=0 rx_held=0 tx_frames=2 tx_dropped=0' <<<"$out" ||
  fail "expected 2 Status frames from the Ethernet controller"

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1234567" </dev/null 2>&1)
code=$?
[ $code -eq 4 ] || { printf '%s\n' "$out"; fail "a bad option should exit 4, got $code"; }
grep -q '^bad option: hz=1234567' <<<"$out" || fail "bad option not named"
echo "qemu_boot_firmware: ok"
