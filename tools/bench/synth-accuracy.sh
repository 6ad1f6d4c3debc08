#!/usr/bin/env bash
# synth-accuracy (design §7): one voice per sine implementation over a 10-minute note at 1 kHz and 10 kHz:
# max |error| against the double reference, host ns per voice sample and per sine call.
# Run by scripts/bench with the build directory as $1.
set -euo pipefail
cmake --build "$1" -j2 --target bench_synth_accuracy >&2
exec "$1/bench/bench_synth_accuracy"
