#!/usr/bin/env bash
# sim-linearisation (design §12): CPU time of one linearisation of the plant's exponential integrator at
# string stiffnesses 10³–10⁷ N/m, and of a step on a cached one (a few seconds). Run by scripts/bench
# with the build directory as $1.
set -euo pipefail
cmake --build "$1" -j2 --target bench_sim_linearisation >&2
"$1/bench/bench_sim_linearisation"
