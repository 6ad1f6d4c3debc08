#!/usr/bin/python3
"""Driver of the midi-parse benchmark (python3 standard library only); tools/bench/midi-parse.sh runs it.

Usage: midi_parse.py HMP [--rounds N] [--big-rounds N] FILE...

For each file, in rounds that take turns between the tools (so that load on the machine hits them alike):
- hmp: `HMP info --json FILE` to /dev/null, wall time of the process, peak RSS from wait4();
- midicsv: `midicsv FILE /dev/null`, wall time of the process;
- mido: mido_pairing.py FILE in Debian's /usr/bin/python3, the parse + note pairing time it measures
  inside the interpreter (start-up and import excluded).
Each tool's figure is its best round. Last, hmp's start-up alone (`hmp --version`), which is most of its
time on small files. Prints the JSON lines of SPEC §2 on stdout.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MIDO_PYTHON = "/usr/bin/python3"  # the pyenv python3 that may come first on PATH has no mido
BIG_FILE_BYTES = 1 << 20          # files at least this big get --big-rounds rounds (mido takes seconds)
MIB = 1 << 20


def run_timed(argv):
    """Wall seconds and peak RSS (MiB) of one process whose output is discarded."""
    start = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if proc.returncode != 0:
        sys.exit(f"midi-parse: {' '.join(argv)} failed ({proc.returncode}): {err.strip()}")
    return seconds, usage.ru_maxrss / 1024.0  # ru_maxrss is in KiB on Linux


def hmp_notes(hmp, path):
    out = subprocess.run([hmp, "info", "--json", path], check=True, capture_output=True, text=True).stdout
    return sum(t["note_count"] for t in json.loads(out)["tracks"])


def mido_round(path):
    out = subprocess.run([MIDO_PYTHON, os.path.join(HERE, "mido_pairing.py"), path], check=True,
                         capture_output=True, text=True).stdout
    result = json.loads(out)
    return result["seconds"], result["notes"]


def line(metric, value, unit, params):
    print(json.dumps({"bench": "midi-parse", "metric": metric, "value": round(value, 6), "unit": unit,
                      "params": params}), flush=True)


def measure(hmp, path, label, rounds):
    size = os.path.getsize(path)
    notes = hmp_notes(hmp, path)
    best = {"hmp": float("inf"), "midicsv": float("inf"), "mido": float("inf")}
    peak_rss = 0.0
    for _ in range(rounds):
        seconds, rss = run_timed([hmp, "info", "--json", path])
        best["hmp"] = min(best["hmp"], seconds)
        peak_rss = max(peak_rss, rss)
        best["midicsv"] = min(best["midicsv"], run_timed(["midicsv", path, "/dev/null"])[0])
        seconds, mido_notes = mido_round(path)
        best["mido"] = min(best["mido"], seconds)
        if mido_notes != notes:  # the same pairing rule must find the same notes
            print(f"midi-parse: {label}: hmp pairs {notes} notes, mido {mido_notes}", file=sys.stderr)
    base = {"file": label, "bytes": size, "notes": notes}
    for tool in ("hmp", "mido", "midicsv"):
        line("seconds", best[tool], "s", {"tool": tool, **base, "rounds": rounds})
    line("speedup_vs_mido", best["mido"] / best["hmp"], "x", {**base, "goal": 50})
    line("speedup_vs_midicsv", best["midicsv"] / best["hmp"], "x", {**base, "goal": 2})
    limit = 3 * size / MIB + 20
    line("peak_rss_mb", peak_rss, "MiB", {"tool": "hmp", **base, "limit_mb": round(limit, 2)})


def startup(hmp, rounds):
    """hmp's process start-up alone (`hmp --version`): the floor of every hmp figure above."""
    seconds = min(run_timed([hmp, "--version"])[0] for _ in range(rounds))
    line("startup_seconds", seconds, "s", {"tool": "hmp", "command": "hmp --version", "rounds": rounds})


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hmp")
    ap.add_argument("files", nargs="+", help="FILE or LABEL=FILE (the label names it in the output)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--big-rounds", type=int, default=3)
    args = ap.parse_args()
    for item in args.files:
        label, _, path = item.rpartition("=")
        label = label or path
        rounds = args.big_rounds if os.path.getsize(path) >= BIG_FILE_BYTES else args.rounds
        print(f"midi-parse: {label} ({rounds} rounds)", file=sys.stderr)
        measure(args.hmp, path, label, rounds)
    startup(args.hmp, args.rounds)


if __name__ == "__main__":
    main()
