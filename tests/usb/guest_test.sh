#!/usr/bin/env bash
# The USB test against a real Linux kernel (label usb; docs/usb.md, "Linux guest test"): boots Debian's own
# kernel under qemu-system-x86_64 with an xHCI controller and a usb-redir device wired to hmp-usb-sim (the
# firmware core and our USB stack, natively), and runs tests/usb/guest_checks.sh in the guest: the kernel's
# enumeration (sysfs), hid-generic and hidraw, `hmp devices`, a 10 s passage played with `hmp play --device
# hid`, an unplug mid-song and the re-plug. Here, on the host side: pulls the device out and back in when
# the guest asks, then checks every guest line and the play log against the song's notes (hmp info).
#
# usage: guest_test.sh BIN_DIR REPO_DIR CACHE_DIR
set -uo pipefail
bin=$1 repo=$2 cache=$3
song="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
tmp=$(mktemp -d)
rig_pid= qemu_pid=
cleanup() {
  [ -n "$qemu_pid" ] && kill "$qemu_pid" 2>/dev/null
  [ -n "$rig_pid" ] && kill "$rig_pid" 2>/dev/null
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$repo/tests/usb/guest-image.sh" "$cache" "$tmp/initramfs" "$repo/tests/usb/guest_checks.sh" \
  "$bin/hmp" "$bin/hmp-full" "$song=/opt/data/song.mid" || fail "could not make the guest"

"$bin/hmp-usb-sim" --socket "$tmp/usb.sock" 2> "$tmp/rig.log" &
rig_pid=$!
for _ in $(seq 50); do [ -S "$tmp/usb.sock" ] && break; sleep 0.1; done
[ -S "$tmp/usb.sock" ] || { cat "$tmp/rig.log"; fail "hmp-usb-sim did not listen"; }

# Emulation (TCG), even where /dev/kvm exists: nested KVM on CI machines hung the guest; TCG boots in ~5 s.
accel=(-accel tcg)
mkfifo "$tmp/console"
timeout 240 qemu-system-x86_64 -M q35 "${accel[@]}" -m 768 -nographic -no-reboot -monitor none \
  -kernel "$cache/vmlinuz" -initrd "$tmp/initramfs" \
  -append "console=ttyS0 quiet loglevel=4 panic=-1" \
  -device qemu-xhci -chardev socket,id=usbredir,path="$tmp/usb.sock" -device usb-redir,chardev=usbredir \
  < /dev/null > "$tmp/console" 2>&1 &
qemu_pid=$!

# Follow the guest: answer its unplug/replug requests, keep every line.
while IFS= read -r line; do
  line=${line%$'\r'}
  printf '%s\n' "$line" >> "$tmp/guest.log"
  case $line in
    "guest: unplug now") kill -USR1 "$rig_pid" ;;
    "guest: replug now") kill -USR2 "$rig_pid" ;;
  esac
done < "$tmp/console"
wait "$qemu_pid"
qemu_rc=$?
qemu_pid=

# Readable on failure: the guest's lines and the kernel's USB messages, the rig's log.
grep -a -v "scheduled_tick" "$tmp/guest.log" | tail -80
echo "--- hmp-usb-sim:"
cat "$tmp/rig.log"
[ "$qemu_rc" -eq 0 ] || fail "QEMU exited with $qemu_rc (timeout: 124)"
# (The console puts terminal escapes before the first line: match anywhere in the line.)
grep -a -q "guest: done fail=0" "$tmp/guest.log" || fail "a guest check failed (lines above)"
oks=$(grep -a -c "guest: ok " "$tmp/guest.log")
[ "$oks" -eq 22 ] || fail "$oks guest checks passed, 22 expected"

# The passage: every note of the flute that starts in [30 s, 40 s) was started by the device on its
# scheduled tick; none late, lost or rejected.
sed -n '/guest: log begin/,/guest: log end/p' "$tmp/guest.log" | grep -a '^{' > "$tmp/play.log"
"$bin/hmp" info "$song" --json --notes > "$tmp/song.json" || fail "hmp info failed"
python3 - "$tmp/song.json" "$tmp/play.log" <<'PY' || fail "the play log does not match the song"
import json, sys
song = json.load(open(sys.argv[1]))
track = next(t for t in song["tracks"] if "flute" in (t.get("name", "") + t.get("instrument", "")).lower())
want = sorted(n["start_s"] for n in song["notes"] if n["track"] == track["index"] and 30.0 <= n["start_s"] < 40.0)
lines = [json.loads(l) for l in open(sys.argv[2]) if l.strip()]
started = [l for l in lines if "summary" not in l]
summary = [l["summary"] for l in lines if "summary" in l]
assert summary, "no summary line"
s = summary[-1]
got = sorted(l["start_s"] for l in started)
off = [l for l in started if l["actual_tick"] != l["scheduled_tick"]]
print(f"passage: {len(want)} flute notes in [30, 40) s; device started {len(started)}; off their tick {len(off)}; summary {s}")
assert len(got) == len(want) and all(abs(a - b) < 1e-3 for a, b in zip(got, want)), "started notes differ from the song's"
assert not off, f"{len(off)} notes off their scheduled tick"
assert s["late"] == 0 and s["rejected"] == 0 and s["notes_played"] == s["notes_sent"] == len(want), "late/rejected/lost"
PY
echo "PASS: $oks guest checks; the passage played through hidraw with every note on its tick"
