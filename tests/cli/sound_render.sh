#!/usr/bin/env bash
# `hmp render SONG --sound --out FILE.wav` (design §17): the song's own sound, all tracks, as a
# 44.1 kHz stereo WAV; the whole song plus 2 s of tail, or the --from/--to passage exactly; not silent;
# bad combinations exit 2 with one line; an existing file stays without -f; --track stays required for
# the haptic renders; with no SoundFont on the machine nothing is written (exit 1, one line).
set -u
hmp="$1"; repo="$2"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
probe() { ffprobe -v error -show_entries stream="$2" -of default=noprint_wrappers=1:nokey=1 "$1" | tr '\n' ' ' | sed 's/ $//'; }

run render "$demo" --sound --from 30 --to 32.5 --out "$tmp/passage.wav"
check "passage rc" 0 "$rc"
check "passage format" "pcm_f32le 44100 2 2.500000" "$(probe "$tmp/passage.wav" codec_name,sample_rate,channels,duration)"
# Not silence: the passage's loudest sample (ffmpeg's volumedetect) is well above −40 dBFS.
peak=$(ffmpeg -v info -i "$tmp/passage.wav" -af volumedetect -f null - 2>&1 | sed -n 's/.*max_volume: \(-*[0-9.]*\) dB.*/\1/p')
check "passage is heard" "yes" "$(awk -v p="$peak" 'BEGIN { print (p > -40) ? "yes" : "no" }')"

song_s=$("$hmp" info "$demo" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["duration_s"])')
run render "$demo" --sound --from 300 --out "$tmp/end.wav"
check "to the end plus 2 s" "$(python3 -c "print(f'{$song_s + 2 - 300:.2f}')")" "$(python3 -c "print(f'{float(\"$(probe "$tmp/end.wav" duration)\"):.2f}')")"

# A --to past the sound's end is that end, however large; within the 2 s after the last event it is kept.
run render "$demo" --sound --from 300 --to 1e300 --out "$tmp/far.wav"
check "--to 1e300: to the end plus 2 s" "$(python3 -c "print(f'{$song_s + 2 - 300:.2f}')")" "$(python3 -c "print(f'{float(\"$(probe "$tmp/far.wav" duration)\"):.2f}')")"
run render "$demo" --sound --from "$(python3 -c "print($song_s + 0.5)")" --out "$tmp/tail.wav"
check "--from in the tail: rc" 0 "$rc"
check "--from in the tail: 1.5 s" "1.50" "$(python3 -c "print(f'{float(\"$(probe "$tmp/tail.wav" duration)\"):.2f}')")"

for bad in "--out $tmp/x.csv" "--out $tmp/x.wav --audible" "--out $tmp/x.wav --from 5 --to 5" "--out $tmp/x.wav --from -1" \
  "--out $tmp/x.wav --to nan" "--out $tmp/x.wav --to inf" "--out $tmp/x.wav --from 1e300"; do
  run render "$demo" --sound $bad
  check "$bad: rc" 2 "$rc"
  check "$bad: one line" 1 "$(wc -l <<<"$err")"
  check "$bad: no file" no "$([ -e "$tmp/x.wav" ] && echo yes || echo no)"
done
run render "$demo" --sound --from 1e300 --out "$tmp/x.wav"
check "--from 1e300: says where the sound ends" 1 "$(grep -c -- "--from 1e+300: the song's sound ends at" <<<"$err")"

run render "$demo" --out "$tmp/x.csv"
check "no --track, no --sound: rc" 2 "$rc"
check "no --track, no --sound: says what" 1 "$(grep -c -- '--track' <<<"$err")"

# No SoundFont on the machine (every standard place hidden by an empty tmpfs in a user and mount
# namespace): the file would be silence, so nothing is written and the one line says what to install.
sounds_hidden() {
  unshare -rm sh -c 'for d in /usr/share/sounds /usr/share/soundfonts; do
    [ -d "$d" ] && { mount -t tmpfs none "$d" || exit 99; }; done; exec "$@"' sh "$@"
}
if sounds_hidden true 2>/dev/null; then
  sounds_hidden "$hmp" render "$demo" --sound --to 1 --out "$tmp/nosf.wav" >"$tmp/out" 2>"$tmp/err"; rc=$?
  check "no SoundFont: rc" 1 "$rc"
  check "no SoundFont: the line" "error: --sound: no General MIDI SoundFont found (install fluid-soundfont-gm, or name one with --soundfont)" "$(<"$tmp/err")"
  check "no SoundFont: no file" no "$([ -e "$tmp/nosf.wav" ] && echo yes || echo no)"
else
  echo "note: no user and mount namespace here; the render without a SoundFont is not checked"
fi

echo "keep" >"$tmp/keep.wav"
run render "$demo" --sound --to 1 --out "$tmp/keep.wav"
check "existing file: rc" 2 "$rc"
check "existing file: untouched" "keep" "$(<"$tmp/keep.wav")"
exit $fail
