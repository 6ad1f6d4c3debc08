#!/usr/bin/python3
"""Driver of the midi-parse benchmark (python3 standard library only); tools/bench/midi-parse.sh runs it.

Usage: midi_parse.py HMP LOADER [--rounds N] [--big-rounds N] FILE...

For each file, in rounds that take turns between the tools (so that load on the machine hits them alike):
first rounds of the in-process figures (the loader, then mido), then rounds of the whole commands (hmp,
then midicsv, after one untimed run of each), so that neither command runs right after a Python
interpreter, which leaves caches and TLB cold and costs any command ~0.07 ms:
- hmp, whole command: `HMP info --json FILE` to /dev/null, wall time of the process, peak RSS from wait4()
  (a floor applies: Linux counts a child's peak from before its exec, i.e. this driver's own, so a figure
  equal to driver_floor_mb means "at most that"; `/usr/bin/time -f %M` shows the program's own);
- hmp, in process: `LOADER --repeat 3 FILE` (bench_midi_parse_inprocess), the time of midi::load_song
  (read + parse + pair) measured inside the process: the first load (cold, the figure compared with mido)
  and the best of the 3 (warm);
- midicsv: `midicsv FILE /dev/null`, wall time of the process;
- mido: mido_pairing.py FILE in Debian's /usr/bin/python3, the parse + note pairing time it measures
  inside the interpreter (start-up and import excluded).
Each tool's figure is its best round. Like is compared with like: speedup_vs_mido is in-process against
in-process, speedup_vs_midicsv whole command against whole command. Last, hmp's start-up alone
(`hmp --version`), which is most of its command's time on small files. Prints the JSON lines of design §2
on stdout.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MIDO_PYTHON = "/usr/bin/python3"  # the pyenv python3 that may come first on PATH has no mido
BIG_FILE_BYTES = 1 << 20          # files at least this big get --big-rounds rounds (mido takes seconds)
MIB = 1 << 20
LOADER_REPEAT = 3                 # in-process loads per round (the first is the cold one)


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


def loader_round(loader, path):
    out = subprocess.run([loader, "--repeat", str(LOADER_REPEAT), path], check=True, capture_output=True,
                         text=True).stdout
    result = json.loads(out)
    return result["first_seconds"], result["best_seconds"], result["notes"]


def measure(hmp, loader, path, label, rounds):
    size = os.path.getsize(path)
    notes = hmp_notes(hmp, path)
    tools = ("hmp", "hmp_load_cold", "hmp_load_warm", "mido", "midicsv")
    best = {tool: float("inf") for tool in tools}
    peak_rss = 0.0
    # The in-process rounds (loader, mido) first, then the whole commands in rounds of their own. A
    # command run right after a Python interpreter (mido) starts ~0.07 ms slower (caches and TLB refilled),
    # which is a larger share of a 0.6 ms command than of a 1.1 ms one; in their own rounds each of the two
    # commands runs right after the other, one untimed run of each before the first round.
    for _ in range(rounds):
        cold, warm, loaded = loader_round(loader, path)
        best["hmp_load_cold"] = min(best["hmp_load_cold"], cold)
        best["hmp_load_warm"] = min(best["hmp_load_warm"], warm)
        seconds, mido_notes = mido_round(path)
        best["mido"] = min(best["mido"], seconds)
        for tool, count in (("mido", mido_notes), ("the in-process loader", loaded)):
            if count != notes:  # the same pairing rule must find the same notes
                print(f"midi-parse: {label}: hmp info pairs {notes} notes, {tool} {count}", file=sys.stderr)
    hmp_argv = [hmp, "info", "--json", path]
    midicsv_argv = ["midicsv", path, "/dev/null"]
    run_timed(hmp_argv)
    run_timed(midicsv_argv)
    for _ in range(rounds):
        seconds, rss = run_timed(hmp_argv)
        best["hmp"] = min(best["hmp"], seconds)
        peak_rss = max(peak_rss, rss)
        best["midicsv"] = min(best["midicsv"], run_timed(midicsv_argv)[0])
    base = {"file": label, "bytes": size, "notes": notes}
    whole = "whole command"
    inproc = "in process"
    scopes = {
        "hmp": {"tool": "hmp", "scope": whole, "command": "hmp info --json FILE"},
        "hmp_load_cold": {"tool": "hmp", "scope": inproc, "work": "midi::load_song, first in the process"},
        "hmp_load_warm": {"tool": "hmp", "scope": inproc,
                          "work": f"midi::load_song, best of {LOADER_REPEAT} in the process"},
        "mido": {"tool": "mido", "scope": inproc, "work": "MidiFile + note pairing, once in the interpreter"},
        "midicsv": {"tool": "midicsv", "scope": whole, "command": "midicsv FILE /dev/null"},
    }
    for tool in tools:
        line("seconds", best[tool], "s", {**scopes[tool], **base, "rounds": rounds})
    line("speedup_vs_mido", best["mido"] / best["hmp_load_cold"], "x",
         {**base, "goal": 50, "compares": "in process vs in process (hmp: first load_song; mido: parse + pairing)"})
    line("speedup_vs_midicsv", best["midicsv"] / best["hmp"], "x",
         {**base, "goal": 2, "compares": "whole command vs whole command (hmp info --json; midicsv)"})
    limit = 3 * size / MIB + 20
    floor = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # this driver's peak, inherited
    line("peak_rss_mb", peak_rss, "MiB",
         {"tool": "hmp", "command": "hmp info --json FILE", **base, "limit_mb": round(limit, 2),
          "driver_floor_mb": round(floor, 2)})


def startup(hmp, rounds):
    """hmp's process start-up alone (`hmp --version`): the floor of every hmp figure above."""
    seconds = min(run_timed([hmp, "--version"])[0] for _ in range(rounds))
    line("startup_seconds", seconds, "s", {"tool": "hmp", "command": "hmp --version", "rounds": rounds})


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hmp")
    ap.add_argument("loader", help="bench_midi_parse_inprocess")
    ap.add_argument("files", nargs="+", help="FILE or LABEL=FILE (the label names it in the output)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--big-rounds", type=int, default=3)
    args = ap.parse_args()
    for item in args.files:
        label, _, path = item.rpartition("=")
        label = label or path
        rounds = args.big_rounds if os.path.getsize(path) >= BIG_FILE_BYTES else args.rounds
        print(f"midi-parse: {label} ({rounds} rounds)", file=sys.stderr)
        measure(args.hmp, args.loader, path, label, rounds)
    startup(args.hmp, args.rounds)


if __name__ == "__main__":
    main()
