#!/usr/bin/env bash
# `hmp render SONG --track T --out FILE.mp4` from the command line (docs/exports.md): the demo's flute over a
# short passage, without a display, gives an MP4 that ffprobe reads as H.264 1280x720 at 60 fps with the
# song's AAC sound (and the haptic signal as a second stream with --haptic-audio), the right number of
# frames; options that cannot work exit 2 with one line naming the option, before any work; an existing
# file is not replaced without -f (and stays as it was); a file that cannot be written, or an export stopped
# by Ctrl-C, leaves nothing behind.
set -u
hmp="$1"; repo="$2"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
run_env=(env -u DISPLAY -u WAYLAND_DISPLAY)  # no display, as on a server
probe() {  # probe FILE ENTRIES STREAMS: ffprobe's values for the streams selected, on one line
  ffprobe -v error -count_frames -select_streams "$3" -show_entries "$2" -of default=noprint_wrappers=1:nokey=1 "$1" |
    tr '\n' ' ' | sed 's/ $//'
}

run render "$demo" --track flute --from 30 --to 32 --out "$tmp/flute.mp4" --haptic-audio
check "render rc" 0 "$rc"
check "summary line" 1 "$(grep -c 'flute.mp4: 120 frames, 2.00 s of video' <<<"$err")"
check "video stream" "h264 1280 720 60/1 120" "$(probe "$tmp/flute.mp4" stream=codec_name,width,height,r_frame_rate,nb_read_frames v:0)"
check "audio streams" "aac 44100 2 aac 44100 1" "$(probe "$tmp/flute.mp4" stream=codec_name,sample_rate,channels a)"
check "no temporary file" "" "$(ls "$tmp" | grep part)"

# Options that cannot work: one line, exit 2, nothing written.
for bad in "--fps 24" "--fps 0" "--size 1279x720" "--size big" "--crf 99" "--video-preset warp" "--audible"; do
  run render "$demo" --track flute --to 1 --out "$tmp/bad.mp4" $bad
  check "$bad: rc" 2 "$rc"
  check "$bad: one line" 1 "$(wc -l <<<"$err")"
  check "$bad: names the option" 1 "$(grep -c -- "${bad%% *}" <<<"$err")"
  check "$bad: no file" "no" "$([ -e "$tmp/bad.mp4" ] && echo yes || echo no)"
done

# An existing file stays unless -f.
echo "precious" >"$tmp/keep.mp4"
run render "$demo" --track flute --to 1 --out "$tmp/keep.mp4"
check "existing file: rc" 2 "$rc"
check "existing file: untouched" "precious" "$(<"$tmp/keep.mp4")"
# A setting that cannot work is named first, even onto an existing file (-f would not help there).
run render "$demo" --track flute --to 1 --out "$tmp/keep.mp4" --crf 99
check "existing file, --crf 99: rc" 2 "$rc"
check "existing file, --crf 99: names --crf" 1 "$(grep -c -- '--crf 99: out of 0..51' <<<"$err")"
check "existing file, --crf 99: untouched" "precious" "$(<"$tmp/keep.mp4")"
run render "$demo" --track flute --to 1 --out "$tmp/keep.mp4" -f
check "-f replaces: rc" 0 "$rc"
check "-f replaces: a video now" "h264" "$(probe "$tmp/keep.mp4" stream=codec_name v:0)"

# A folder that is not there: an error, and no file or temporary file anywhere.
run render "$demo" --track flute --to 1 --out "$tmp/none/x.mp4"
check "missing folder: fails" "yes" "$([ "$rc" -ne 0 ] && echo yes || echo no)"
check "missing folder: one line" 1 "$(wc -l <<<"$err")"

# Ctrl-C halfway: the export stops, says so, and leaves neither the file nor its temporary.
env -u DISPLAY -u WAYLAND_DISPLAY "$hmp" render "$demo" --track flute --to 120 --out "$tmp/stopped.mp4" 2>"$tmp/err" &
pid=$!
for _ in $(seq 100); do [ -e "$tmp/stopped.mp4.part" ] && break; sleep 0.05; done
sleep 0.3
kill -INT $pid; wait $pid; rc=$?
check "interrupted: rc" 1 "$rc"
check "interrupted: says so" 1 "$(grep -c 'interrupted' "$tmp/err")"
check "interrupted: nothing left" "" "$(ls "$tmp" | grep stopped)"

exit $fail
