#!/usr/bin/env bash
# bench_sim_work_precision (scripts/bench sim-work-precision) on 0.1 s of frame_edge at 10⁴ N/m with the
# default integrator, classical Runge–Kutta and CVODE: every line is JSON with the fields
# docs/performance.md's table and its figures read; Runge–Kutta's derivative count is four a step, the
# same ticks at every step size; --replot draws the run's own figure again, byte for byte; a file that is
# not the benchmark's output, and every bad option value, exits 2 with one line naming it, before any run.
set -u
bench="$1"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

mkdir "$tmp/run" "$tmp/again"
"$bench" --seconds 0.1 --scenes frame_edge --stiffness 1e4 --integrators exponential,rk4,cvode \
  --plot-dir "$tmp/run" >"$tmp/wp.jsonl" 2>"$tmp/err" || { echo "FAIL: the benchmark:"; cat "$tmp/err"; fail=1; }
python3 - "$tmp/wp.jsonl" <<'EOF' || fail=1
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
params = [r["params"] for r in rows if r["bench"] == "sim-work-precision"]
need = {"scene", "stiffness_n_per_m", "integrator", "steps_per_tick", "default", "ok", "force_error_rel",
        "finger_force_error_rel", "band_force_error_rel", "realtime_factor", "reference_convergence",
        "claimed", "tick_force_error_rel", "derivatives", "failure"}
problems = [f"line {i + 1} lacks {sorted(need - p.keys())}" for i, p in enumerate(params) if need - p.keys()]
if len(params) != len(rows) or not params:
    problems.append(f"{len(rows)} lines, {len(params)} of the benchmark")
defaults = [p for p in params if p["default"]]
if len(defaults) != 1 or defaults[0]["integrator"] != "exponential" or not defaults[0]["tick_force_error_rel"] > 0:
    problems.append(f"the default: {defaults}")
for p in params:
    if p["ok"] != (p["failure"] is None) or p["ok"] != (p["derivatives"] is not None):
        problems.append(f"{p['integrator']} {p['steps_per_tick']}: ok {p['ok']}, failure {p['failure']}, "
                        f"derivatives {p['derivatives']}")
ticks = {p["derivatives"] / (4 * p["steps_per_tick"]) for p in params if p["integrator"] == "rk4" and p["ok"]}
if len(ticks) != 1 or ticks != {100}:
    problems.append(f"rk4's derivatives / (4 x steps per tick): {sorted(ticks)}, not 100 ticks")
if not any(p["integrator"] == "cvode" and p["ok"] and p["derivatives"] > 0 for p in params):
    problems.append("no cvode point with its derivatives")
for problem in problems:
    print("FAIL:", problem)
sys.exit(1 if problems else 0)
EOF

"$bench" --replot "$tmp/wp.jsonl" --plot-dir "$tmp/again" 2>"$tmp/err" || { echo "FAIL: --replot"; cat "$tmp/err"; fail=1; }
cmp -s "$tmp/run/sim-work-precision-frame_edge.png" "$tmp/again/sim-work-precision-frame_edge.png" ||
  { echo "FAIL: --replot drew another figure than the run's"; ls -l "$tmp/run" "$tmp/again"; fail=1; }

for bad in 'not json' '{"bench":"sim-work-precision","params":{"scene":"frame_edge"}}'; do
  { head -2 "$tmp/wp.jsonl"; echo "$bad"; } >"$tmp/bad.jsonl"
  "$bench" --replot "$tmp/bad.jsonl" --plot-dir "$tmp/again" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  { [ $rc -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "bad.jsonl:3:" "$tmp/err"; } ||
    { echo "FAIL: --replot of '$bad' -> rc=$rc:"; cat "$tmp/err"; fail=1; }
done
"$bench" --replot "$tmp/none.jsonl" >"$tmp/out" 2>"$tmp/err"
rc=$?
{ [ $rc -eq 2 ] && grep -q "none.jsonl: cannot open" "$tmp/err"; } || { echo "FAIL: a missing file -> rc=$rc"; fail=1; }
for args in "--seconds abc" "--seconds 0" "--seconds -1" "--seconds nan" "--seconds 21" "--stiffness 0" \
  "--stiffness 1e4,x" "--stiffness 1e10" "--stiffness ," "--scenes frame_edge,nope" "--steps 3" \
  "--integrators exponential,rk5" "--plot-dir $tmp/none"; do
  word=${args%% *}
  # shellcheck disable=SC2086  # the option and its value are two words
  "$bench" $args >"$tmp/out" 2>"$tmp/err"
  rc=$?
  { [ $rc -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q -- "$word" "$tmp/err" && [ ! -s "$tmp/out" ]; } ||
    { echo "FAIL: $args -> rc=$rc:"; cat "$tmp/err"; fail=1; }
done
exit $fail
