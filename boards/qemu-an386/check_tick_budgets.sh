#!/usr/bin/env bash
# Test qemu_tick_budgets: the firmware tick's instruction budgets (design §8), on every test run. The
# counts come from the firmware-tick benchmark (tools/bench/firmware-tick.sh: the bench image under
# QEMU -icount, one instruction per nanosecond of virtual time), which are exact and the same on a busy
# machine, so this is not a timed test. Fails naming each budget exceeded:
#   the heaviest tick with 16 voices ≤ 1,500 (1 kHz and 10 kHz), the split 10 kHz tick ≤ 2,500,
#   the whole tick with the drive ≤ 12,000.
# Usage: check_tick_budgets.sh REPOSITORY CROSS-BUILD-DIRECTORY
set -euo pipefail
repo=${1:?usage: check_tick_budgets.sh REPOSITORY CROSS-BUILD-DIRECTORY}
export HMP_QEMU_BUILD_DIR=${2:?usage: check_tick_budgets.sh REPOSITORY CROSS-BUILD-DIRECTORY}
cd "$repo"
bash tools/bench/firmware-tick.sh unused | python3 -c '
import json, sys
budget = {False: 1500, "split": 2500, True: 12000}
checked, failed = 0, 0
for line in sys.stdin:
    d = json.loads(line)
    p = d.get("params", {})
    if d["metric"] != "instructions_per_tick_max" or p.get("voices") != 16:
        continue
    limit = budget[p["drive"]]
    ok = d["value"] <= limit
    checked += 1
    failed += not ok
    print("%s: 16 voices, %s Hz, drive %s: %d instructions (budget %d)" %
          ("ok" if ok else "FAIL", p["tick_hz"], p["drive"], d["value"], limit))
if checked != 5:
    print("FAIL: %d budgets measured, 5 expected" % checked)
    sys.exit(1)
sys.exit(1 if failed else 0)
'
