#!/usr/bin/env bash
# usb-path (docs/usb.md): instructions the firmware's USB device stack spends per report on the Cortex-M4F
# build, counted under `qemu-system-arm -icount shift=0` as firmware-tick counts (the image
# hmp_fw_qemu_an386_usb_bench, boards/qemu-an386/usb_bench_main.cpp; a run of 1000 nops must count 1000).
# Worst of 200 rounds each:
#   out          the interrupt OUT completion of a 5-note report: the stack's handling plus the core's
#                Core::on_packet (decoding into the inbox); out_stack is the stack's share alone;
#   in           one device report queued (copied, IN transfer started) plus its IN completion.
# The controller's FIFO copy is not counted (a stub controller). Goal: ≤ 400 instructions each way.
# Run by scripts/bench with the host build directory as $1 (unused: the image comes from the cross tree).
set -euo pipefail
cross="${HMP_QEMU_BUILD_DIR:-build/qemu-an386}"
qemu="${QEMU_SYSTEM_ARM:-qemu-system-arm}"
command -v "$qemu" >/dev/null || { echo "usb-path: $qemu not installed" >&2; exit 1; }
[ -f "$cross/CMakeCache.txt" ] || cmake --preset qemu-an386 -B "$cross" >&2
cmake --build "$cross" -j2 --target hmp_fw_qemu_an386_usb_bench >&2
image="$cross/boards/qemu-an386/hmp_fw_qemu_an386_usb_bench.elf"
out=$(timeout 120 "$qemu" -M mps2-an386 -nographic -monitor none -serial null \
        -semihosting-config enable=on,target=native -icount shift=0,sleep=off \
        -kernel "$image" </dev/null 2>&1) || { printf '%s\n' "$out" >&2; exit 1; }
nops=$(sed -n 's/^calibration: nops=1000 measured=\(-\{0,1\}[0-9]*\)$/\1/p' <<<"$out")
if [ -z "$nops" ] || [ "$nops" -lt 996 ] || [ "$nops" -gt 1004 ]; then
  printf '%s\n' "$out" >&2
  echo "usb-path: instruction counter off (1000 nops counted as '${nops}')" >&2
  exit 1
fi
grep -q '^WARNING' <<<"$out" && { printf '%s\n' "$out" >&2; exit 1; }
line=$(grep '^usb ' <<<"$out") || { printf '%s\n' "$out" >&2; exit 1; }
for metric in out out_stack on_packet queue in_complete in; do
  value=$(tr ' ' '\n' <<<"$line" | sed -n "s/^$metric=\\(-\\{0,1\\}[0-9]*\\)$/\\1/p")
  printf '{"bench":"usb-path","metric":"instructions_%s","value":%s,"unit":"instructions","params":{"board":"qemu-an386","report":"notes x5","goal":400}}\n' "$metric" "$value"
done
