# Sourced by the benchmarks that count Cortex-M4F instructions on the qemu-an386 image (firmware-tick,
# usb-path): builds an image of the cross tree (build/qemu-an386, or $HMP_QEMU_BUILD_DIR) and runs it under
# `qemu-system-arm -icount shift=0`, where every guest instruction is 1 ns of virtual time
# (boards/qemu-an386/instruction_counter.hpp).
#   an386_counted BENCH TARGET SECONDS [APPEND]
# prints the image's output; fails, showing it, when QEMU fails, when the image's calibration (a run of
# 1000 nops) counts anything but 1000 ± 4 — then none of the numbers mean anything — or when it printed a
# WARNING line.
an386_counted() {
  local bench=$1 target=$2 seconds=$3 append=${4:-}
  local cross="${HMP_QEMU_BUILD_DIR:-build/qemu-an386}" qemu="${QEMU_SYSTEM_ARM:-qemu-system-arm}"
  command -v "$qemu" >/dev/null || { echo "$bench: $qemu not installed" >&2; return 1; }
  [ -f "$cross/CMakeCache.txt" ] || cmake --preset qemu-an386 -B "$cross" >&2
  cmake --build "$cross" -j2 --target "$target" >&2
  local out nops
  out=$(timeout "$seconds" "$qemu" -M mps2-an386 -nographic -monitor none -serial null \
          -semihosting-config enable=on,target=native -icount shift=0,sleep=off \
          -kernel "$cross/boards/qemu-an386/$target.elf" ${append:+-append "$append"} </dev/null 2>&1) ||
    { printf '%s\n' "$out" >&2; return 1; }
  nops=$(sed -n 's/^calibration: nops=1000 measured=\(-\{0,1\}[0-9]*\)$/\1/p' <<<"$out")
  if [ -z "$nops" ] || [ "$nops" -lt 996 ] || [ "$nops" -gt 1004 ]; then
    printf '%s\n' "$out" >&2
    echo "$bench: instruction counter off (1000 nops counted as '${nops}')" >&2
    return 1
  fi
  if grep -q '^WARNING' <<<"$out"; then printf '%s\n' "$out" >&2; return 1; fi
  printf '%s\n' "$out"
}
