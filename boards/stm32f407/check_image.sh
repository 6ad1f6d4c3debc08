#!/usr/bin/env bash
# check_image.sh IMAGE.elf: the stm32f407 image as a board would take it, checked against the chip's
# facts (RM0090 memory map, ARMv7-M reset behaviour), not against the linker script:
#   - the .bin starts with the vector table: word 0 (initial SP) inside SRAM 0x20000000–0x20020000 and
#     8-byte aligned; word 1 (reset vector) odd (Thumb) and inside the .bin's flash range 0x08000000+;
#   - every other vector is zero (reserved) or odd and inside the image;
#   - the .dfu is the .bin plus a valid DFU suffix for the ROM bootloader 0483:df11 (dfu-suffix --check)
#     whose bcdDevice is the version in the image's name (hmp_fw_stm32f407-MAJOR.MINOR.PATCH), as BCD;
#   - the sizes fit (size-report.sh).
set -euo pipefail
elf=$1
bin=${elf%.elf}.bin dfu=${elf%.elf}.dfu
here=$(dirname "${BASH_SOURCE[0]}")
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -s "$bin" ] || fail "no $bin"
size=$(stat -c %s "$bin")
mapfile -t words < <(od -An -v -t u4 -w4 -N $((98 * 4)) "$bin" | tr -d ' ')
[ "${#words[@]}" -eq 98 ] || fail "the .bin is shorter than a vector table (${#words[@]} words)"
sp=${words[0]} reset=${words[1]}
(( sp > 0x20000000 && sp <= 0x20020000 )) || fail "initial SP $(printf 0x%08x "$sp") is not inside SRAM"
(( sp % 8 == 0 )) || fail "initial SP $(printf 0x%08x "$sp") is not 8-byte aligned"
(( reset % 2 == 1 )) || fail "reset vector $(printf 0x%08x "$reset") is not a Thumb address"
(( reset > 0x08000000 && reset < 0x08000000 + size )) || fail "reset vector $(printf 0x%08x "$reset") is outside the image"
for i in $(seq 2 97); do
  v=${words[$i]}
  [ "$v" -eq 0 ] && continue
  (( v % 2 == 1 && v > 0x08000000 && v < 0x08000000 + size )) || fail "vector $i = $(printf 0x%08x "$v") is not a handler in the image"
done
echo "vector table: SP $(printf 0x%08x "$sp"), reset $(printf 0x%08x "$reset"), 96 more vectors in the image"

[ -s "$dfu" ] || fail "no $dfu"
check=$(dfu-suffix --check "$dfu" 2>&1) || fail "dfu-suffix --check: $check"
grep -qi "vendor id.*0x0483" <<<"$check" || fail "DFU suffix vendor is not 0x0483: $check"
grep -qi "product id.*0xdf11" <<<"$check" || fail "DFU suffix product is not 0xdf11: $check"
[ "$(stat -c %s "$dfu")" -eq $((size + 16)) ] || fail "the .dfu is not the .bin plus a 16-byte suffix"
cmp -s -n "$size" "$bin" "$dfu" || fail "the .dfu does not start with the .bin"
[[ $(basename "$elf") =~ -([0-9]+)\.([0-9])\.([0-9])\.elf$ ]] || fail "$elf: no version in the name"
bcd=$(printf '0x%02d%d%d' "${BASH_REMATCH[1]}" "${BASH_REMATCH[2]}" "${BASH_REMATCH[3]}")
grep -qi "bcd device:[[:space:]]*$bcd\$" <<<"$check" || fail "DFU suffix bcdDevice is not $bcd: $check"
echo "dfu suffix: 0483:df11, bcdDevice $bcd, 16 bytes after the .bin"

"$here/size-report.sh" "${SIZE:-arm-none-eabi-size}" "$elf"
echo "PASS"
