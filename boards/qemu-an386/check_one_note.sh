#!/usr/bin/env bash
# Test qemu_boot_one_note: boots the demo image, requires exit code 0 (the image's own self-check) and
# re-checks the printed values independently, so a broken self-check or a silent image still fails.
# Usage: check_one_note.sh IMAGE.elf
set -uo pipefail
image=${1:?usage: check_one_note.sh IMAGE.elf}
here=$(dirname "${BASH_SOURCE[0]}")
command -v "${QEMU_SYSTEM_ARM:-qemu-system-arm}" >/dev/null || { echo "FAIL: qemu-system-arm not installed"; exit 1; }

# stdin from /dev/null: -nographic would otherwise read the test runner's terminal.
out=$(timeout 20 "$here/run.sh" "$image" </dev/null 2>&1)
code=$?
printf '%s\n' "$out"
fail() { echo "FAIL: $*"; exit 1; }
[ $code -eq 124 ] && fail "QEMU timed out (image hung)"
[ $code -eq 0 ] || fail "image exited with $code"

grep -q '^HMP qemu-an386 one-note demo$' <<<"$out" || fail "banner missing"
grep -q '^startup: data=ok bss=ok ctors=ok fpu=ok$' <<<"$out" || fail "startup probes"
grep -q '^RESULT: PASS$' <<<"$out" || fail "no PASS line"

# The note was 50 Hz at amplitude 0.5 for one second (see main.cpp): plausible values only.
stats=$(grep '^stats:' <<<"$out") || fail "no stats line"
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<" $stats"; }
awk -v lo="$(field min)" -v hi="$(field max)" -v x="$(field up_crossings)" 'BEGIN {
  ok = (hi >= 0.49 && hi <= 0.51 && lo <= -0.49 && lo >= -0.51 && x >= 49 && x <= 51)
  exit ok ? 0 : 1 }' || fail "implausible stats: $stats"
grep -q '^counters: started=1 stolen=0 rejected=0 active_after=0$' <<<"$out" || fail "engine counters"
echo "qemu_boot_one_note: ok"
