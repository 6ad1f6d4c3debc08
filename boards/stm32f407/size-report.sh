#!/usr/bin/env bash
# size-report.sh SIZE-TOOL IMAGE.elf: flash, RAM and CCM use of the stm32f407 image against the chip
# (1 MiB flash, 128 KiB SRAM, 64 KiB CCM). Fails when a region is over (the linker would already refuse
# most of these; this says by how much, and states the margins after every build).
set -euo pipefail
size=$1 elf=$2
declare -A bytes=()
while read -r section sz addr; do
  [[ $sz =~ ^[0-9]+$ ]] || continue
  bytes[$section]=$sz
done < <("$size" -A -d "$elf")
b() { echo "${bytes[$1]:-0}"; }
flash=$(( $(b .isr_vector) + $(b .text) + $(b .ARM.exidx) + $(b .preinit_array) + $(b .init_array) + $(b .fini_array) + $(b .data) ))
ram=$(( $(b .data) + $(b .bss) + $(b .stack) ))
ccm=$(b .ccm)
status=0
report() {
  local what=$1 used=$2 total=$3
  awk -v w="$what" -v u="$used" -v t="$total" 'BEGIN { printf "%-6s %8d of %8d bytes (%5.1f %%)\n", w, u, t, 100 * u / t }'
  if [ "$used" -gt "$total" ]; then echo "error: $what over by $((used - total)) bytes" >&2; status=1; fi
}
echo "$(basename "$elf"):"
report flash "$flash" $((1024 * 1024))
report ram "$ram" $((128 * 1024))
report ccm "$ccm" $((64 * 1024))
exit $status
