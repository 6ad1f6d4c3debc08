#!/usr/bin/env bash
# sim-work-precision (design §12): force error against run time for every plant integrator and step size,
# and each integrator's largest stable step in the nominal and extreme scenes. Draws the figure into the
# build tree ($1/bench/sim-work-precision.png, path on stderr): a benchmark never rewrites the docs —
# scripts/doc-plots --bench copies a figure worth keeping into docs/img/. Run by scripts/bench with the
# build directory as $1.
set -euo pipefail
cmake --build "$1" -j2 --target bench_sim_work_precision >&2
plot="$1/bench/sim-work-precision.png"
"$1/bench/bench_sim_work_precision" --plot "$plot"
echo "sim-work-precision: figure in $plot" >&2
