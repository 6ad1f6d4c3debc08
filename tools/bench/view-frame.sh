#!/usr/bin/env bash
# view-frame (docs/view.md): the animation window's cost per frame at 1280×720 under Mesa's
# llvmpipe on a private Xvfb, for generated songs of 1k, 10k and 100k notes and the 620k-note file of
# midi-parse (tools/bench/gen_big_midi.py), each drawing only the visible notes (ours) and every note of
# the song (--all: what players that upload and draw all notes pay). Run by scripts/bench with the build
# directory as $1. Needs xvfb (scripts/packages.txt).
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target hmp bench_view_frame >&2 ||
  { cmake "$build" >&2 && cmake --build "$build" -j2 --target hmp bench_view_frame >&2; }
mkdir -p "$build/bench"

# A free display for a private Xvfb, stopped on exit.
display=""
for n in $(seq 140 180); do
  [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ] || { display=":$n"; break; }
done
[ -n "$display" ] || { echo "view-frame: no free X display number" >&2; exit 1; }
Xvfb "$display" -screen 0 1600x1000x24 -nolisten tcp -noreset >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null || true' EXIT
for _ in $(seq 100); do [ -e "/tmp/.X11-unix/X${display#:}" ] && break; sleep 0.05; done
export DISPLAY=$display

frames=${HMP_VIEW_FRAMES:-600}
for notes in 1000 10000 100000 620000; do
  song="$build/bench/midi-parse-big-$notes.mid"  # the same generator and cache as midi-parse
  if [ ! -f "$song" ] || [ tools/bench/gen_big_midi.py -nt "$song" ]; then
    echo "view-frame: generating $song" >&2
    /usr/bin/python3 tools/bench/gen_big_midi.py "$song.tmp" --notes "$notes" && mv "$song.tmp" "$song"
  fi
  echo "view-frame: $notes notes" >&2
  "$build/bench/bench_view_frame" "$song" "generated-$notes" "$frames"
  # Every note each frame: fewer frames for the big songs (each one costs a lot).
  all_frames=$frames
  [ "$notes" -ge 100000 ] && all_frames=60
  "$build/bench/bench_view_frame" "$song" "generated-$notes" "$all_frames" --all
done
