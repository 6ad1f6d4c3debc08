#!/usr/bin/env bash
# Boots the USB guest (tests/usb/guest-image.sh) under qemu-system-x86_64 with an xHCI controller and a
# usb-redir device wired to hmp-usb-sim, runs GUEST_SCRIPT in it, and writes every console line to
# CONSOLE_LOG (the rig's log to CONSOLE_LOG.rig). Pulls the device out when the guest prints
# "guest: unplug now" and plugs it back on "guest: replug now". Exits with QEMU's status (124: timeout).
#
# usage: run-guest.sh BIN_DIR CACHE_DIR GUEST_SCRIPT CONSOLE_LOG [PROGRAM | SRC=GUEST_PATH]...
set -uo pipefail
bin=$1 cache=$2 script=$3 log=$4
shift 4
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tmp=$(mktemp -d)
rig_pid= qemu_pid=
cleanup() {
  [ -n "$qemu_pid" ] && kill "$qemu_pid" 2>/dev/null
  [ -n "$rig_pid" ] && kill "$rig_pid" 2>/dev/null
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
: > "$log"

"$here/guest-image.sh" "$cache" "$tmp/initramfs" "$script" "$@" || { echo "run-guest: could not make the guest" >&2; exit 1; }
"$bin/hmp-usb-sim" --socket "$tmp/usb.sock" 2> "$log.rig" &
rig_pid=$!
for _ in $(seq 50); do [ -S "$tmp/usb.sock" ] && break; sleep 0.1; done
[ -S "$tmp/usb.sock" ] || { cat "$log.rig" >&2; echo "run-guest: hmp-usb-sim did not listen" >&2; exit 1; }

# Emulation (TCG), even where /dev/kvm exists: nested KVM on CI machines hung the guest; TCG boots in ~5 s.
mkfifo "$tmp/console"
timeout 240 qemu-system-x86_64 -M q35 -accel tcg -m 768 -nographic -no-reboot -monitor none \
  -kernel "$cache/vmlinuz" -initrd "$tmp/initramfs" \
  -append "console=ttyS0 quiet loglevel=4 panic=-1" \
  -device qemu-xhci -chardev socket,id=usbredir,path="$tmp/usb.sock" -device usb-redir,chardev=usbredir \
  < /dev/null > "$tmp/console" 2>&1 &
qemu_pid=$!
while IFS= read -r line; do
  line=${line%$'\r'}
  printf '%s\n' "$line" >> "$log"
  case $line in
    *"guest: unplug now") kill -USR1 "$rig_pid" ;;
    *"guest: replug now") kill -USR2 "$rig_pid" ;;
  esac
done < "$tmp/console"
wait "$qemu_pid"
rc=$?
qemu_pid=
exit $rc
