#!/usr/bin/env bash
# envelope-measure: `hmp envelope measure --all`, every GM program of the installed SoundFont rendered
# by FluidSynth and fitted (host/measure/); target ≤ 10 s on the 2-core machine. Also the mean and the
# worst RMS error of the Eq. 9–10 fits. Run by scripts/bench with the build directory as $1.
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target hmp >&2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
start=$(date +%s.%N)
"$build/bin/hmp" envelope measure --all >"$out"
end=$(date +%s.%N)
python3 - "$out" "$start" "$end" <<'PY'
import json, sys
path, start, end = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
rows = [l.split() for l in open(path) if l[:4].strip().isdigit()]
rms = [float(r[-1]) for r in rows]
def emit(metric, value, unit):
    print(json.dumps({"bench": "envelope-measure", "metric": metric, "value": round(value, 4), "unit": unit,
                      "params": {"programs": len(rows), "target_s": 10}}, separators=(",", ":")))
emit("wall", end - start, "s")
emit("fit_rms_error_mean", sum(rms) / len(rms), "full scale")
emit("fit_rms_error_max", max(rms), "full scale")
PY
