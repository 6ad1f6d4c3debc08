#!/usr/bin/env bash
# The USB test against a real Linux kernel (label usb; docs/usb.md, "Linux guest test"): boots Debian's own
# kernel under qemu-system-x86_64 with an xHCI controller and a usb-redir device wired to hmp-usb-sim (the
# firmware core and our USB stack, natively), and runs tests/usb/guest_checks.sh in the guest: the kernel's
# enumeration (sysfs), hid-generic and hidraw, `hmp devices`, a 10 s passage played with `hmp play --device
# hid`, an unplug mid-song that ends the run (--exit-on-device-loss), the re-plug, and an unplug that the
# player waits out, playing on when the device is back. Here, on the host side: pulls the device out and back in when
# the guest asks, then checks every guest line and the play log against the song's notes (hmp info).
#
# usage: guest_test.sh BIN_DIR REPO_DIR CACHE_DIR
set -uo pipefail
bin=$1 repo=$2 cache=$3
song="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$repo/tests/usb/run-guest.sh" "$bin" "$cache" "$repo/tests/usb/guest_checks.sh" "$tmp/guest.log" \
  "$bin/hmp" "$bin/../lib/hmp/hmp-usb.so=/opt/lib/hmp/hmp-usb.so" "$song=/opt/data/song.mid"
qemu_rc=$?

# Readable on failure: the guest's lines and the kernel's USB messages, the rig's log.
grep -a -v "scheduled_tick" "$tmp/guest.log" | tail -80
echo "--- hmp-usb-sim:"
cat "$tmp/guest.log.rig"
[ "$qemu_rc" -eq 0 ] || fail "QEMU exited with $qemu_rc (timeout: 124)"
# (The console puts terminal escapes before the first line: match anywhere in the line.)
grep -a -q "guest: done fail=0" "$tmp/guest.log" || fail "a guest check failed (lines above)"
oks=$(grep -a -c "guest: ok " "$tmp/guest.log")
[ "$oks" -eq 25 ] || fail "$oks guest checks passed, 25 expected"

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
started = [l for l in lines if "scheduled_tick" in l]
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
# The passage unplugged for a second after 3 s: the notes after the resume (the song time "playing on at"
# names) each once and on their tick; the notes before the unplug each once, but for those in flight when
# it went (their Started reports went with it).
sed -n '/guest: resume log begin/,/guest: resume log end/p' "$tmp/guest.log" | grep -a '^{' > "$tmp/resume.log"
grep -a -o 'is back: playing on at [0-9:.]*' "$tmp/guest.log" | head -1 > "$tmp/resumed_at"
python3 - "$tmp/song.json" "$tmp/resume.log" "$tmp/resumed_at" <<'PY' || fail "the resumed passage does not match the song"
import json, sys
song = json.load(open(sys.argv[1]))
track = next(t for t in song["tracks"] if "flute" in (t.get("name", "") + t.get("instrument", "")).lower())
want = sorted(n["start_s"] for n in song["notes"] if n["track"] == track["index"] and 30.0 <= n["start_s"] < 40.0)
lines = [json.loads(l) for l in open(sys.argv[2]) if l.strip()]
started = [l for l in lines if "scheduled_tick" in l]
m, s = open(sys.argv[3]).read().split()[-1].split(":")
resumed = int(m) * 60 + float(s) - 0.05  # the text is rounded to tenths
after = [w for w in want if w >= resumed + 0.05]
count = lambda t: sum(1 for l in started if abs(l["start_s"] - t) < 1e-3)
print(f"resume at {resumed + 0.05:.1f} s: {len(after)} notes after it, device started {len(started)} in all")
assert 1.0 < resumed + 0.05 - 30.0 < 8.0, "resumed far from where it was unplugged"
assert len(after) >= 5, "too few notes after the resume to tell"
assert all(count(w) == 1 for w in after), "a note after the resume was not started exactly once"
assert all(count(w) == 1 for w in want if w < resumed - 0.3), "a note before the unplug was not started once"
assert all(count(w) <= 1 for w in want), "a note started twice"
off = [l for l in started if l["start_s"] >= resumed and l["actual_tick"] != l["scheduled_tick"]]
assert not off, f"{len(off)} notes after the resume off their scheduled tick"
PY
echo "PASS: $oks guest checks; the passage played through hidraw with every note on its tick, and again across an unplug"
