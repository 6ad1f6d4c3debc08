#!/usr/bin/env bash
# hmp info / render / --config on the command line: bad input exits 2 with one line naming the problem;
# good input produces the promised outputs; nothing existing is overwritten without --force.
set -u
hmp="$1"; repo="$2"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"


# --- info
expect_bad "no such" info "$tmp/missing.mid"
printf 'hello, not midi' >"$tmp/junk.mid"
expect_bad "MThd" info "$tmp/junk.mid"
: >"$tmp/empty.mid"
expect_bad "byte" info "$tmp/empty.mid"
expect_ok info "$demo"
grep -q "Flute (73)" "$tmp/out" || { echo "FAIL: info table lacks the flute"; fail=1; }
expect_ok info "$demo" --json
/usr/bin/python3 - "$tmp/out" <<'PY' || fail=1
import json, sys
j = json.load(open(sys.argv[1]))
t = j["tracks"]
assert len(t) == 9, len(t)
assert t[1]["program"] == 73 and t[1]["envelope"] == "flute", t[1]
assert t[6]["envelope"] == "contrabass" and t[7]["envelope"] == "harpsichord"
assert all(k in t[1] for k in ("index", "name", "channels", "instrument", "note_count", "key_min", "key_max", "distinct_keys"))
assert "notes" not in j and j["duration_s"] > 300 and j["tempo_changes"][0]["bpm"] == 120
PY
expect_ok info "$demo" --json --notes
/usr/bin/python3 - "$tmp/out" <<'PY' || fail=1
import json, sys
j = json.load(open(sys.argv[1]))
n = j["notes"]
assert len(n) == sum(t["note_count"] for t in j["tracks"])
assert set(n[0]) == {"track", "channel", "key", "velocity", "start_s", "end_s"}, n[0]
assert all(x["end_s"] >= x["start_s"] for x in n)
PY

# --- play without --track: the first track whose instrument has a Table 1 envelope, and the line says
# which; a song with none (here GM program 100, a synth effect: the square preset) plays its first track
# with notes, and the line says that instead
expect_ok play "$demo" --no-audio --no-view --device sim --to 0.1
grep -q '^haptic track 1 "flute" (Flute) (the first whose instrument has a Table 1 envelope;' "$tmp/err" ||
  { echo "FAIL: play's default track line: $(cat "$tmp/err")"; fail=1; }
printf 'MThd\0\0\0\6\0\0\0\1\1\340MTrk\0\0\0\20\0\300\144\0\220\74\144\203\140\200\74\0\0\377\57\0' >"$tmp/fx.mid"
expect_ok play "$tmp/fx.mid" --no-audio --no-view --device sim
grep -q '(no instrument has a Table 1 envelope: the first with notes;' "$tmp/err" ||
  { echo "FAIL: play's fallback track line: $(cat "$tmp/err")"; fail=1; }

# --- render: track selection and options
expect_bad "ambiguous" render "$demo" --track violin --out "$tmp/a.csv"
expect_bad "no track matches" render "$demo" --track kazoo --out "$tmp/a.csv"
# A song without a note (a header and one empty track): said so, not an internal error
printf 'MThd\0\0\0\6\0\1\0\1\1\340MTrk\0\0\0\4\0\377\57\0' >"$tmp/silent.mid"
expect_bad "no track matches (the song has no notes)" render "$tmp/silent.mid" --track flute --out "$tmp/a.csv"
expect_bad "the song has no notes to play" play "$tmp/silent.mid" --track 0 --device sim --no-audio --no-view
expect_bad "the song lasts 0 s" render "$tmp/silent.mid" --track 0 --to 5 --out "$tmp/a.csv"  # not "--from 0 --to 5: empty"
expect_bad "no such track" render "$demo" --track 42 --out "$tmp/a.csv"
expect_bad "alias" render "$demo" --track flute --freq-range 50:500 --out "$tmp/a.csv"
expect_bad "freq-range" render "$demo" --track flute --freq-range 300:50 --out "$tmp/a.csv"
expect_bad "freq-range" render "$demo" --track flute --freq-range abc --out "$tmp/a.csv"
expect_bad "amp-range" render "$demo" --track flute --amp-range-db 30:7.5 --out "$tmp/a.csv"
# wider than the device's 16-bit amplitude: every note but the loudest below its smallest step (all zeros)
expect_bad "at most 96 dB apart" render "$demo" --track flute --amp-range-db 7.5:1e5 --out "$tmp/a.csv"
expect_bad "at most 96 dB apart" render "$demo" --track flute --amp-range-db -1e300:30 --out "$tmp/a.csv"
expect_ok render "$demo" --track flute --to 2 --amp-range-db -66:30 --out "$tmp/wide.csv"
expect_bad "mapping" render "$demo" --track flute --mapping loud --out "$tmp/a.csv"
expect_bad "envelope" render "$demo" --track flute --envelope kazoo --out "$tmp/a.csv"
expect_bad "polyphony" render "$demo" --track flute --polyphony all --out "$tmp/a.csv"
expect_bad ".png, .ahap, .haptic or .mp4" render "$demo" --track flute --out "$tmp/a.mp3"
expect_bad "audible" render "$demo" --track flute --audible --out "$tmp/a.csv"
expect_bad "empty window" render "$demo" --track flute --from 5 --to 4 --out "$tmp/a.csv"
expect_bad "from" render "$demo" --track flute --from -1 --out "$tmp/a.csv"
# Times past the song (310 s): a start there is refused, an end there is the song's end, however large.
expect_bad "the song ends at 310.000 s" render "$demo" --track flute --from 1e300 --out "$tmp/a.csv"
expect_bad "to inf" render "$demo" --track flute --to inf --out "$tmp/a.csv"
expect_ok render "$demo" --track flute --from 305 --to 1e300 --out "$tmp/tail.csv"
expect_ok render "$demo" --track flute --from 305 --out "$tmp/tail_default.csv"
cmp -s "$tmp/tail.csv" "$tmp/tail_default.csv" && [ "$(wc -l <"$tmp/tail.csv")" -gt 5000 ] ||
  { echo "FAIL: --to past the song is not the song's end ($(wc -l <"$tmp/tail.csv") lines)"; fail=1; }
expect_ok render "$demo" --track flute --from 2 --to 3 --out "$tmp/w.csv"
[ "$(head -1 "$tmp/w.csv")" = "t_s,value" ] && [ "$(($(wc -l <"$tmp/w.csv") - 1))" = 1000 ] \
  || { echo "FAIL: window CSV has $(wc -l <"$tmp/w.csv") lines"; fail=1; }
[ "$(sed -n 2p "$tmp/w.csv" | cut -d, -f1)" = 2 ] || { echo "FAIL: window starts at $(sed -n 2p "$tmp/w.csv")"; fail=1; }
# A window equals the same ticks of the whole render (notes sounding into the window included).
expect_ok render "$demo" --track flute --from 0 --to 3 --out "$tmp/full.csv"
diff <(tail -n 1000 "$tmp/full.csv") <(tail -n +2 "$tmp/w.csv") >/dev/null || { echo "FAIL: window differs from full render"; fail=1; }
expect_ok render "$demo" --track 1 --to 2 --out "$tmp/w.wav"
expect_ok render "$demo" --track flute --to 2 --audible --out "$tmp/aud.wav"
expect_ok render "$demo" --track contrabass --to 4 --out "$tmp/p.png"
[ "$(head -c 8 "$tmp/p.png" | od -An -tx1 | tr -d ' ')" = 89504e470d0a1a0a ] || { echo "FAIL: not a PNG"; fail=1; }
/usr/bin/python3 - "$tmp/w.wav" "$tmp/aud.wav" <<'PY' || fail=1
import struct, sys
def rate(p):
    b = open(p, "rb").read(64)
    assert b[:4] == b"RIFF" and b[8:12] == b"WAVE"
    return struct.unpack("<I", b[24:28])[0]
assert rate(sys.argv[1]) == 1000, rate(sys.argv[1])
assert rate(sys.argv[2]) == 44100, rate(sys.argv[2])
PY
before=$(md5sum <"$tmp/w.csv")
expect_bad "exists" render "$demo" --track flute --from 2 --to 3 --out "$tmp/w.csv"
[ "$(md5sum <"$tmp/w.csv")" = "$before" ] || { echo "FAIL: existing output modified"; fail=1; }

# --- config
printf '[mapping]\nfrq_range = [50, 250]\n' >"$tmp/typo.toml"
expect_bad "mapping.frq_range" render "$demo" --track flute --config "$tmp/typo.toml" --out "$tmp/c.csv"
printf '[mapping\nmode = "paper"\n' >"$tmp/broken.toml"
expect_bad "broken.toml:" render "$demo" --track flute --config "$tmp/broken.toml" --out "$tmp/c.csv"
printf '[presets.soft]\nattack_ms = 10\nsustain_pct = 150\n' >"$tmp/range.toml"
expect_bad "sustain_pct" render "$demo" --track flute --config "$tmp/range.toml" --out "$tmp/c.csv"
# A config is good or bad for every command: [plant] (hmp sim's) refused by play too; a bad value named with
# the file it is in
printf '[plant]\nintegrator = "cvode"\n' >"$tmp/plant.toml"
expect_bad "plant.toml: plant.integrator cvode: unknown" play "$demo" --track flute --to 1 --device sim --no-audio --no-view --config "$tmp/plant.toml"
printf '[mapping]\nmode = "papr"\n' >"$tmp/papr.toml"
expect_bad "papr.toml: unknown mapping mode 'papr'" render "$demo" --track flute --to 1 --config "$tmp/papr.toml" --out "$tmp/c.csv"
# A value checked once every config and option is in (ranges, fade, envelope, the program tables): named by
# the file and key that set it last, not by the option the user did not give; the option when it wins.
printf '[mapping]\nfreq_range = [250, 50]\n' >"$tmp/fr.toml"
printf '[envelope]\nend_fade_ms = -1\ndefault = "nosuch"\n' >"$tmp/fade.toml"
printf '[gm]\n"7" = "flute"\n"73" = "nosuch"\n' >"$tmp/gm73.toml"
expect_bad "fr.toml: mapping.freq_range: need 0 < min ≤ max (got 250:50)" info "$demo" --config "$tmp/fr.toml"
expect_bad "error: --freq-range: need 0 < min ≤ max (got 260:50)" info "$demo" --config "$tmp/fr.toml" --freq-range 260:50
expect_ok info "$demo" --config "$tmp/fr.toml" --freq-range 60:200
expect_bad "fade.toml: envelope.end_fade_ms: must be in \[0, 1000\]" info "$demo" --config "$tmp/gm73.toml" --config "$tmp/fade.toml"
expect_bad "fade.toml: envelope.default: unknown preset 'nosuch'" info "$demo" --config "$tmp/fade.toml" --end-fade-ms 2
expect_bad "gm73.toml: gm.73 names unknown preset 'nosuch'" info "$demo" --config "$tmp/gm73.toml"
# [device]: checked when the config is read, before any device (play told only after it had connected)
for bad in "peak_force_n = -5|'device.peak_force_n' must be in (0, 20] N" "peak_force_n = 1e300|'device.peak_force_n' must be in (0, 20] N" \
  "direction = [0.0, 0.0, 0.0]|'device.direction' must be a finite, non-zero vector"; do
  printf '[device]\n%s\n' "${bad%%|*}" >"$tmp/device.toml"
  expect_bad "device.toml: ${bad#*|}" play "$demo" --track flute --to 1 --device sim --no-audio --no-view --config "$tmp/device.toml"
  expect_bad "device.toml: ${bad#*|}" sim "$demo" --track flute --to 1 --config "$tmp/device.toml"
done
printf '[device]\ndirection = [0.0, 2.0, 0.0]\n' >"$tmp/device.toml"  # any length: the unit vector along it
expect_ok play "$demo" --track flute --from 2 --to 2.5 --device sim --no-audio --no-view --config "$tmp/device.toml"
printf '[gm]\n"73" = "nothing"\n' >"$tmp/gm.toml"
expect_bad "nothing" render "$demo" --track flute --config "$tmp/gm.toml" --out "$tmp/c.csv"
# A [gm] key is the whole of a program number 0–127: a NUL (TOML's \u0000) does not end it.
for key in 128 -1 7x 1e1 "" '5\u0000' ' 5' +5; do
  printf '[gm]\n"%s" = "organ"\n' "$key" >"$tmp/gm_key.toml"
  shown=${key%\\u0000}  # the message shows the NUL as \0 (a pattern for grep: \\0)
  [ "$shown" = "$key" ] || shown="$shown\\\\0"
  expect_bad "gm: key '$shown' must be a GM program number" render "$demo" --track flute \
    --config "$tmp/gm_key.toml" --out "$tmp/c.csv"
done
# An integer beyond 2^53 is a number out of range, not "not a finite number"
printf '[presets.p]\nattack_ms = 9223372036854775807\n' >"$tmp/huge.toml"
expect_bad "'presets.p': durations must be in \[0, 1e7\] ms" info "$demo" --config "$tmp/huge.toml"
# A preset named like an envelope mode could never be chosen
printf '[presets.measured]\nattack_ms = 5\n' >"$tmp/mode.toml"
expect_bad "presets.measured: 'measured' is an envelope mode" info "$demo" --config "$tmp/mode.toml"
# One program, or one preset name, given twice in other spellings: refused, not the last one silently
printf '[gm]\n"5" = "organ"\n"05" = "flute"\n' >"$tmp/gm_twice.toml"
expect_bad "gm: program 5 is given twice" info "$demo" --config "$tmp/gm_twice.toml"
printf '[presets.Mine]\nattack_ms = 5\n[presets.mine]\nattack_ms = 50\n' >"$tmp/case.toml"
expect_bad "presets.mine: another preset has this name (case does not count)" info "$demo" --config "$tmp/case.toml"
# A user preset mapped to the flute's program changes the render; square via the config equals --envelope square.
printf '[presets.plain]\nsustain_pct = 100\nfinal_pct = 100\n[gm]\n"73" = "plain"\n' >"$tmp/plain.toml"
expect_ok render "$demo" --track flute --to 4 --config "$tmp/plain.toml" --out "$tmp/plain.csv"
expect_ok render "$demo" --track flute --to 4 --envelope square --out "$tmp/square.csv"
expect_ok render "$demo" --track flute --to 4 --out "$tmp/auto.csv"
cmp -s "$tmp/plain.csv" "$tmp/square.csv" || { echo "FAIL: user preset 'plain' should equal square"; fail=1; }
cmp -s "$tmp/plain.csv" "$tmp/auto.csv" && { echo "FAIL: config preset had no effect"; fail=1; }

# --- an empty value is no value, for every command: CLI11 alone took it as 0 or as not given
expect_bad "--crf: an empty value" render "$demo" --track 1 --to 1 --out "$tmp/empty.mp4" --crf ''
expect_bad "--to: an empty value" render "$demo" --track 1 --to '' --out "$tmp/empty.csv"
expect_bad "--ms: an empty value" tone --freq 100 --amp 0.5 --ms '' --instrument flute --out "$tmp/empty.csv"
expect_bad "--end-fade-ms: an empty value" tone --freq 100 --amp 0.5 --ms 50 --end-fade-ms '' --instrument flute --out "$tmp/empty.csv"
expect_bad "--to: an empty value" play "$demo" --track 1 --to '' --device sim --no-audio --no-view
expect_bad "--log: an empty value" play "$demo" --track 1 --to 1 --device sim --no-audio --no-view --log ''
expect_bad "--max-step: an empty value" sim "$demo" --track 1 --to 1 --max-step ''
expect_bad "--channel: an empty value" live --channel '' --no-audio --no-view
expect_bad "--seed: an empty value" study --out "$tmp" --participant p --seed '' --no-audio --no-view
# a seed is digits alone: CLI11 took -1 as 2^64 − 1 and wrote that into the session's journal
expect_bad "--seed: -1 is not a whole number from 0 to 18446744073709551615" study --out "$tmp" --participant p --seed -1 --no-audio --no-view
expect_bad "--seed: 18446744073709551616 is not a whole number" study --out "$tmp" --participant p --seed 18446744073709551616 --no-audio --no-view
[ -e "$tmp/study-p.journal" ] && { echo "FAIL: a journal written for a bad seed"; fail=1; }
[ -e "$tmp/empty.csv" ] || [ -e "$tmp/empty.mp4" ] && { echo "FAIL: an output written for an empty value"; fail=1; }
# An output render cannot write: every kind it can is named (the message was tone's, .csv .wav .png only)
expect_bad "--out $tmp/a.txt: use a .csv, .wav, .png, .ahap, .haptic or .mp4 file" render "$demo" --track 1 --to 1 --out "$tmp/a.txt"
# Options that contradict each other, or that the output would ignore, are refused instead of ignored
expect_bad "--track excludes --sound" render "$demo" --sound --track 1 --to 1 --out "$tmp/both.wav"
for video in "--crf 30" "--size 640x360" "--fps 30" "--zoom 5" "--video-preset slow" "--haptic-audio" "--no-audio"; do
  expect_bad "${video%% *}: only with --out FILE.mp4" render "$demo" --track 1 --to 1 --out "$tmp/video-only.csv" $video
done
[ -e "$tmp/both.wav" ] || [ -e "$tmp/video-only.csv" ] && { echo "FAIL: an output written for contradicting options"; fail=1; }
expect_bad "--notes requires --json" info "$demo" --notes
expect_bad "--no-view excludes --fullscreen" play "$demo" --track 1 --to 1 --device sim --no-audio --no-view --fullscreen
expect_bad "--no-audio excludes --audio-driver" play "$demo" --track 1 --to 1 --device sim --no-view --no-audio --audio-driver alsa
expect_bad "--no-audio excludes --audio-buffer-ms" view "$demo" --no-audio --audio-buffer-ms 50
# NaN passes CLI11's own range checks
expect_bad "--zoom: nan is not a number from 1 to 120" render "$demo" --track 1 --to 1 --out "$tmp/nan.mp4" --zoom nan
expect_bad "--audio-buffer-ms: nan is not a number from 10 to 1000" play "$demo" --track 1 --to 1 --device sim --no-view --audio-buffer-ms nan
# A --soundfont that is not one is refused before any work, not played or rendered as silence
printf 'not a soundfont' >"$tmp/junk.sf2"
expect_bad "--soundfont $tmp/junk.sf2: not a SoundFont 2 file" play "$demo" --track 1 --to 1 --device sim --no-view --soundfont "$tmp/junk.sf2"
expect_bad "--soundfont $tmp/junk.sf2: not a SoundFont 2 file" render "$demo" --sound --to 1 --out "$tmp/junk.wav" --soundfont "$tmp/junk.sf2"
[ -e "$tmp/nan.mp4" ] || [ -e "$tmp/junk.wav" ] && { echo "FAIL: an output written for a bad value"; fail=1; }

[ $fail -eq 0 ] && echo "song_commands: all passed"
exit $fail
