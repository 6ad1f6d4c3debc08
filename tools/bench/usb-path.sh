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
source "$(dirname "${BASH_SOURCE[0]}")/lib/an386-counted.sh"
out=$(an386_counted usb-path hmp_fw_qemu_an386_usb_bench 120)
line=$(grep '^usb ' <<<"$out") || { printf '%s\n' "$out" >&2; exit 1; }
for metric in out out_stack on_packet queue in_complete in; do
  value=$(tr ' ' '\n' <<<"$line" | sed -n "s/^$metric=\\(-\\{0,1\\}[0-9]*\\)$/\\1/p")
  printf '{"bench":"usb-path","metric":"instructions_%s","value":%s,"unit":"instructions","params":{"board":"qemu-an386","report":"notes x5","goal":400}}\n' "$metric" "$value"
done
