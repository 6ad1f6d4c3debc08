#!/usr/bin/env bash
# sim-work-precision (design §12): error against run time of every plant integrator and step size, and of
# CVODE, in every plant scene at string stiffnesses 10³–10⁷ N/m, against CVODE at rtol 1e-10 (about
# 35 minutes on one core). Draws one figure per scene into the build tree ($1/bench/, paths on stderr): a
# benchmark never rewrites the docs — scripts/doc-plots --bench copies the figures into docs/img/. Run by
# scripts/bench with the build directory as $1; extra arguments in HMP_SIM_WP_ARGS (e.g. "--quick").
set -euo pipefail
cmake --build "$1" -j2 --target bench_sim_work_precision hmp_loadable_modules >&2
# shellcheck disable=SC2086  # the arguments are words on purpose
"$1/bench/bench_sim_work_precision" --plot-dir "$1/bench" ${HMP_SIM_WP_ARGS:-}
