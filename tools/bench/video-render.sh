#!/usr/bin/env bash
# video-render (docs/exports.md): the MP4 export's speed as a multiple of real time, 30 s of the
# demo's flute from 0:30 at 1280×720 60 fps (the goal: ≥ 4× on 2 cores with llvmpipe), with libx264's
# default preset (ultrafast) and two slower ones for the size/speed trade-off, and 1920×1080 for reference.
# Run by scripts/bench with the build directory as $1. Needs no display (EGL surfaceless).
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target bench_video_render >&2 ||
  { cmake "$build" >&2 && cmake --build "$build" -j2 --target bench_video_render >&2; }
mkdir -p "$build/bench"
demo=examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid
seconds=${HMP_VIDEO_SECONDS:-30}
for run in "ultrafast 1280x720 60" "superfast 1280x720 60" "veryfast 1280x720 60" "ultrafast 1920x1080 30"; do
  read -r preset size fps <<<"$run"
  out="$build/bench/video-render.mp4"
  env -u DISPLAY -u WAYLAND_DISPLAY "$build/bench/bench_video_render" "$demo" flute "$seconds" "$preset" "$size" "$fps" "$out"
  echo "video-render: $preset $size $fps fps: $(stat -c %s "$out") bytes" >&2
  rm -f "$out"
done
