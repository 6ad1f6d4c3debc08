#!/usr/bin/env bash
# `hmp flash` without a board (design §3, §13; docs/flashing.md): --dry-run prints each method's command as
# boards/stm32f407/README.md documents it, for a given image and its sibling of the other kind; bad options
# exit 2 with one line; a missing tool names its Debian package, exit 1; no board found (a CI machine has
# none) says how to enter DFU mode, exit 1; the udev rule compiled into hmp is the repository's file, and
# every rule grants uaccess to one VID:PID; --install-udev-rule asks first and, with no terminal, installs
# nothing. The default image (HMP_SOURCE_DIR pointing at a fake source tree, a fake cmake on PATH) is built
# when it is missing or older than its sources and only then; --dry-run only says it would build.
set -u
hmp="$1"; repo="$2"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

# The least that passes hmp's look at an image: a .bin's vector table (the stack pointer 0x20020000 in SRAM,
# the Thumb reset address 0x08000101 in flash), a 32-bit ARM ELF header.
fake_bin() { printf '\000\000\002\040\001\001\000\010' >"$1"; }
fake_elf() { printf '\177ELF\001\001\001\000\000\000\000\000\000\000\000\000\002\000\050\000' >"$1"; }
img="$tmp/my fw"  # a space: the printed command must quote it
fake_elf "$img.elf"; fake_bin "$img.bin"
run flash --dry-run --method dfu --firmware "$img.elf"
check "dfu dry run" "dfu-util -d 0483:df11 -a 0 -s 0x08000000:leave -D '$img.bin'" "$out"; check "dfu rc" 0 "$rc"
run flash --dry-run --method stlink --firmware "$img.bin"
check "stlink dry run" "st-flash --reset write '$img.bin' 0x8000000" "$out"
run flash --dry-run --method openocd --firmware "$img.bin"
check "openocd dry run" "openocd -f board/stm32f4discovery.cfg -c 'program $img.elf verify reset exit'" "$out"

rm "$img.elf"
run flash --dry-run --method openocd --firmware "$img.bin"
check "openocd without a .elf: rc" 2 "$rc"
check "openocd without a .elf: one line" 1 "$(wc -l <<<"$err")"
run flash --board uno
check "bad board rc" 2 "$rc"; check "bad board message" "error: --board uno: unknown board (known: stm32f407)" "$err"
run flash --method jtag
check "bad method rc" 2 "$rc"; check "bad method message" "error: --method jtag: expected dfu, stlink or openocd" "$err"
run flash --firmware "$tmp/none.bin"
check "missing image rc" 2 "$rc"
: >"$tmp/fw.hex"
run flash --firmware "$tmp/fw.hex"
check "wrong kind rc" 2 "$rc"
run flash --timeout-s -1 --firmware "$img.bin"
check "bad timeout rc" 2 "$rc"
# Not an image for the board: refused before any tool runs (a flasher would write it as given).
: >"$tmp/empty.bin"; truncate -s 1025K "$tmp/big.bin"; printf 'MThd\0\0\0\6' >"$tmp/song.bin"; cp /bin/sh "$tmp/host.elf"
for bad in "empty.bin|empty" "big.bin|larger than the board's 1 MiB of flash" \
  "song.bin|does not begin with an stm32f407 vector table" "host.elf|not a 32-bit ARM ELF file"; do
  run flash --dry-run --firmware "$tmp/${bad%%|*}" --method "$([ "${bad%%|*}" = host.elf ] && echo openocd || echo dfu)"
  check "${bad%%|*}: rc" 2 "$rc"
  check "${bad%%|*}: message" "error: $tmp/${bad%%|*}: ${bad#*|}: not a firmware image for the stm32f407" "$err"
done

# No tool on PATH: the package to install.
fake_elf "$img.elf"
PATH="$tmp/empty" run flash --method stlink --firmware "$img.bin"
check "no st-flash rc" 1 "$rc"
check "no st-flash message" "error: st-flash not found — install it: sudo apt install stlink-tools" "$err"
PATH="$tmp/empty" run flash --method dfu --firmware "$img.bin"
check "no dfu-util rc" 1 "$rc"
check "no dfu-util message" "error: dfu-util not found — install it: sudo apt install dfu-util" "$err"
PATH="$tmp/empty" run flash --method openocd --firmware "$img.bin"
check "no openocd rc" 1 "$rc"
check "no openocd message" "error: openocd not found — install it: sudo apt install openocd" "$err"
rm "$img.elf"
# Tools there (fake ones, so nothing real could ever be flashed here), no board: how to get one ready.
mkdir -p "$tmp/bin"
for t in dfu-util st-flash openocd; do printf '#!/bin/sh\necho "FAKE %s RAN"; exit 0\n' "$t" >"$tmp/bin/$t"; chmod +x "$tmp/bin/$t"; done
# Without USB device nodes (a container) libusb lists nothing: devices says why rather than "none".
if [ ! -e /dev/bus/usb ]; then
  run devices --json
  check "no USB: usb_scan_error" 1 "$(grep -c '"usb_scan_error":"no /dev/bus/usb: USB is not visible here' <<<"$out")"
  run devices
  check "no USB: the text says why" 1 "$(grep -c '^boards to flash cannot be looked for: no /dev/bus/usb' <<<"$out")"
fi
if "$hmp" devices --json | grep -q '"kind":"stm32_dfu"'; then
  echo "note: an STM32 in DFU mode is plugged in: the no-board checks are skipped"
else
  PATH="$tmp/bin:$PATH" run flash --method dfu --firmware "$img.bin"
  check "no DFU board rc" 1 "$rc"
  dfu_hint="error: no STM32 in DFU mode found (0483:df11) — hold BOOT0 high (on the STM32F4DISCOVERY: a jumper from BOOT0 to VDD), press RESET, and run hmp flash again"
  # (where libusb cannot look, the line goes on with why: the same hint first)
  check "no DFU board message" "$dfu_hint" "${err:0:${#dfu_hint}}"
  check "no DFU board: one line" 1 "$(wc -l <<<"$err")"
  grep -q "FAKE" <<<"$out" && { echo "FAIL: a tool ran without a board"; fail=1; }
fi
if ! "$hmp" devices --json | grep -q '"kind":"stlink"'; then
  PATH="$tmp/bin:$PATH" run flash --method openocd --firmware "$img.bin"
  # (openocd wants the .elf, which is gone: bad input first)
  check "openocd no elf rc" 2 "$rc"
  fake_elf "$img.elf"
  PATH="$tmp/bin:$PATH" run flash --method stlink --firmware "$img.bin"
  check "no ST-LINK rc" 1 "$rc"
  grep -q "no ST-LINK probe found" <<<"$err" || { echo "FAIL: no-probe hint: [$err]"; fail=1; }
fi

# The default image, in a fake source tree: built (by the fake cmake) when missing or stale, never by a dry run.
src="$tmp/src tree"; mkdir -p "$src/boards/stm32f407" "$src/firmware" "$src/shared"
: >"$src/firmware/core.cpp"
version=$("$hmp" --version | awk '{print $2}')
image="hmp_fw_stm32f407-$version"  # the name the cross tree gives (boards/stm32f407/CMakeLists.txt)
fw="$src/build/stm32f407/boards/stm32f407/$image"
cat >"$tmp/bin/cmake" <<FAKE
#!/bin/sh
echo "FAKE CMAKE \$* in \$(pwd)" | tee -a "\$CMAKE_LOG"
[ -n "\$CMAKE_FAIL" ] && exit 3
if [ "\$1" = --preset ]; then mkdir -p build/stm32f407 && : >build/stm32f407/CMakeCache.txt; fi
if [ "\$1" = --build ]; then
  mkdir -p build/stm32f407/boards/stm32f407
  printf '\000\000\002\040\001\001\000\010' >build/stm32f407/boards/stm32f407/$image.bin
  printf '\177ELF\001\001\001\000\000\000\000\000\000\000\000\000\002\000\050\000' >build/stm32f407/boards/stm32f407/$image.elf
fi
FAKE
chmod +x "$tmp/bin/cmake"
export CMAKE_LOG="$tmp/cmake.log"
HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" run flash --dry-run --method dfu
check "default image dry run" "dfu-util -d 0483:df11 -a 0 -s 0x08000000:leave -D '$fw.bin'" "$out"
check "default image dry run: what it would build" \
  "would first build $image.bin (it does not exist): cd '$src' && cmake --preset stm32f407 && cmake --build --preset stm32f407" "$err"
[ -e "$CMAKE_LOG" ] && { echo "FAIL: a dry run built"; fail=1; }
HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" CMAKE_FAIL=1 run flash --method dfu
check "failed build rc" 1 "$rc"
check "failed build: the build's output shown" "FAKE CMAKE --preset stm32f407 in $src" "$out"
check "failed build message" "error: building the stm32f407 image failed (see above)" "$(tail -n 1 <<<"$err")"
rm -f "$CMAKE_LOG"
if ! "$hmp" devices --json | grep -q '"kind":"stm32_dfu"'; then
  HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" run flash --method dfu
  check "built: the build's steps" "FAKE CMAKE --preset stm32f407 in $src
FAKE CMAKE --build --preset stm32f407 in $src" "$(<"$CMAKE_LOG")"
  check "built, no board: rc" 1 "$rc"
  last=$(tail -n 1 <<<"$err"); check "built, no board: message" "$dfu_hint" "${last:0:${#dfu_hint}}"
  [ -f "$fw.bin" ] || { echo "FAIL: no image after the build"; fail=1; }
  # Up to date now: no build. Configured and stale: only cmake --build.
  rm -f "$CMAKE_LOG"
  HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" run flash --method dfu
  [ -e "$CMAKE_LOG" ] && { echo "FAIL: built an up-to-date image"; fail=1; }
  touch -d '+1 min' "$src/shared/protocol.hpp"
  HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" run flash --dry-run --method dfu
  check "stale: what it would build" \
    "would first build $image.bin (it is older than shared/protocol.hpp): cd '$src' && cmake --build --preset stm32f407" "$err"
  HMP_SOURCE_DIR="$src" PATH="$tmp/bin:$PATH" run flash --method dfu
  check "stale: the build's steps" "FAKE CMAKE --build --preset stm32f407 in $src" "$(<"$CMAKE_LOG")"
fi
HMP_SOURCE_DIR="$tmp/nowhere" run flash --dry-run --method dfu
check "no source tree rc" 2 "$rc"

# The udev rule.
run flash --print-udev-rule
if ! cmp -s "$tmp/out" "$repo/host/flash/70-hmp.rules"; then echo "FAIL: the compiled-in rule differs from host/flash/70-hmp.rules"; fail=1; fi
bad=$(grep -v '^#' "$repo/host/flash/70-hmp.rules" | grep -v '^$' |
      grep -v -E '^SUBSYSTEM=="(usb|hidraw)", ATTRS\{idVendor\}=="[0-9a-f]{4}", ATTRS\{idProduct\}=="[0-9a-f]{4}", TAG\+="uaccess"$')
check "malformed rule lines" "" "$bad"
for id in 1209:0001 0483:df11 0483:3748 0483:374b 0483:374e; do
  grep -q "idVendor}==\"${id%:*}\", ATTRS{idProduct}==\"${id#*:}\"" "$repo/host/flash/70-hmp.rules" || { echo "FAIL: no rule for $id"; fail=1; }
done
run flash --install-udev-rule </dev/null
check "install without a terminal rc" 1 "$rc"
grep -q "from a terminal" <<<"$err" || { echo "FAIL: install without a terminal: [$err]"; fail=1; }
# On a terminal (script(1) gives it one) answering anything but y installs nothing.
if command -v script >/dev/null; then
  out=$(echo n | timeout 20 script -qec "'$hmp' flash --install-udev-rule" /dev/null); rc=$?
  check "install answered n: rc" 1 "$rc"
  # The terminal echoes the "n" where it arrives: before the prompt (the usual case) or, on a loaded
  # machine where hmp asked first, after it.
  answer=$(tr -d '\r' <<<"$out" | grep -A1 -F "Install? [y/N]")
  case "$answer" in
    "Install? [y/N] Nothing installed." | "Install? [y/N] n"$'\n'"Nothing installed.") ;;
    *) echo "FAIL: install answered n: [$out]"; fail=1 ;;
  esac
  grep -q "/etc/udev/rules.d/70-hmp.rules" <<<"$out" || { echo "FAIL: install does not name the target: [$out]"; fail=1; }
fi

[ $fail -eq 0 ] && echo "PASS"
exit $fail
