#!/usr/bin/env bash
# The benchmarks' numeric arguments (tools/bench/arguments.hpp): a value that is not wholly a number in
# range ('5x', 'inf', '0' notes, '2.5' repeats) exits 2 before any work, with one stderr line naming the
# benchmark, the argument and the value, and nothing on stdout.
set -u
bench="$1"  # the folder of the bench_* executables
demo="$2/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

# refused NAME WORD ARGS...: bench_NAME ARGS exits 2 with one line holding "bench_NAME: WORD".
refused() {
  local name="$1" word="$2"; shift 2
  "$bench/bench_$name" "$@" >"$tmp/out" 2>"$tmp/err" </dev/null; local rc=$?
  if [ $rc -ne 2 ] || [ "$(wc -l <"$tmp/err")" -ne 1 ] || [ -s "$tmp/out" ] ||
     ! grep -qF -- "bench_$name: $word" "$tmp/err"; then
    echo "FAIL: bench_$name $* -> rc=$rc, wanted 'bench_$name: $word':"; cat "$tmp/err"; fail=1
  fi
}

refused synth_accuracy "--note-s: '5x' is not a number" --note-s 5x
refused synth_accuracy "--tick-hz: 'inf' is not a whole number" --tick-hz inf
refused synth_accuracy "--tick-hz: '1000.5' is not a whole number" --tick-hz 1000.5
refused audio_haptic_skew "NOTES: '0' is not a whole number from 1" 0
refused e2e_timing "TRACK: '1x' is not a whole number" "$demo" 1x 5
refused e2e_timing "SECONDS: 'nan' is not a number" "$demo" 1 nan
refused live_latency "NOTES: '-3' is not a whole number" sim -3 hmp log
refused live_latency "SPACING_MS: '0' is not a number" sim 10 hmp log 0
refused midi_parse_inprocess "--repeat: '2.5' is not a whole number" --repeat 2.5 "$demo"
refused video_render "SECONDS: '1e400' is not a number" "$demo" flute 1e400 p 64x64 30 "$tmp/v.mp4"
refused video_render "FPS: '0' is not a whole number" "$demo" flute 1 p 64x64 0 "$tmp/v.mp4"
refused view_frame "FRAMES: '99999999999999999999' is not a whole number" "$demo" demo 99999999999999999999
[ -e "$tmp/v.mp4" ] && { echo "FAIL: a refused video_render wrote its output"; fail=1; }

[ $fail -eq 0 ] && echo "bench_arguments: all passed"
exit $fail
