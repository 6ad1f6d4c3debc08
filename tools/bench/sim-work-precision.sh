#!/usr/bin/env bash
# sim-work-precision (design §12): force error against run time for every plant integrator and step size,
# and each integrator's largest stable step in the nominal and extreme scenes. Also redraws
# docs/img/sim-work-precision.png. Run by scripts/bench with the build directory as $1.
set -euo pipefail
cmake --build "$1" -j2 --target bench_sim_work_precision >&2
exec "$1/bench/bench_sim_work_precision" --plot docs/img/sim-work-precision.png
