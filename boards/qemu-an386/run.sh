#!/usr/bin/env bash
# Boots a qemu-an386 image: QEMU's mps2-an386 with semihosting (log on stderr, exit code from the image)
# and -icount shift=0 (one instruction = 1 ns of virtual time), so runs are deterministic and timer
# readings count instructions. UART0 is on stdio. The exit status is the image's.
# Usage: run.sh IMAGE.elf [extra qemu options…]   (QEMU_SYSTEM_ARM overrides the emulator)
set -euo pipefail
image=${1:?usage: run.sh IMAGE.elf [qemu options...]}
shift
exec "${QEMU_SYSTEM_ARM:-qemu-system-arm}" -M mps2-an386 -nographic \
  -semihosting-config enable=on,target=native \
  -icount shift=0,sleep=off \
  -kernel "$image" "$@"
