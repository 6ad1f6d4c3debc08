#!/usr/bin/env python3
"""The tables of docs/performance.md that come from a benchmark, generated from its saved output.

Each generated table sits between two markers in the doc:

    <!-- generated: NAME from docs/bench/FILE by tools/bench/doc_tables.py -->
    | … the table … |
    <!-- end generated -->

NAME picks the renderer below; FILE is the benchmark's output as it printed it (JSON lines, or one JSON
object for a soak), kept next to the doc so that a figure can be traced to the run that gave it. To
change a table, run the benchmark, save its output over FILE and run this with --write; by hand the
table is never edited. --check (the README test command) fails when a table differs from its data.

usage: tools/bench/doc_tables.py --check|--write [DOC]
"""
import importlib.util
import json
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BLOCK = re.compile(r"(<!-- generated: (\S+) from (\S+) by tools/bench/doc_tables.py -->\n)(.*?)(<!-- end generated -->)",
                   re.S)


def json_lines(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.startswith("{")]


def thousands(x):
    return f"{round(x):,}"


def firmware_metric(rows, metric, **params):
    for r in rows:
        if r["metric"] == metric and all(r["params"].get(k) == v for k, v in params.items()):
            return r["value"]
    raise KeyError(f"firmware-tick: no {metric} for {params}")


def firmware_voices(path):
    """16-voice budget table: mean and heaviest tick per number of voices, at 1 and 10 kHz, no drive."""
    rows = json_lines(path)
    out = ["| voices | 1 kHz mean | 1 kHz max | 10 kHz mean | 10 kHz max |", "|---|---|---|---|---|"]
    for v in sorted({r["params"]["voices"] for r in rows if r["params"].get("drive") is False and "voices" in r["params"]}):
        cells = [thousands(firmware_metric(rows, m, voices=v, drive=False, tick_hz=hz))
                 for hz in (1000, 10000) for m in ("instructions_per_tick", "instructions_per_tick_max")]
        if v == 16:
            cells = [f"**{c}**" for c in cells]
        out.append(f"| {'**16**' if v == 16 else v} | " + " | ".join(cells) + " |")
    return out


def firmware_drive(path):
    """The whole drive in the tick (design §8: ≤ 12,000)."""
    rows = json_lines(path)
    out = ["| tick | drive | voices | mean | max |", "|---|---|---|---|---|"]
    for hz, drive, voices in ((1000, False, 16), (1000, True, 0), (1000, True, 16), (10000, True, 0), (10000, True, 16)):
        mean = thousands(firmware_metric(rows, "instructions_per_tick", voices=voices, drive=drive, tick_hz=hz))
        worst = thousands(firmware_metric(rows, "instructions_per_tick_max", voices=voices, drive=drive, tick_hz=hz))
        if drive and voices == 16:
            mean, worst = f"**{mean}**", f"**{worst}**"
        out.append(f"| {hz // 1000} kHz | {'yes' if drive else 'no'} | {voices} | {mean} | {worst} |")
    return out


def firmware_split(path):
    """The split drive at 10 kHz: the tick, the plan, and the worst millisecond."""
    rows = json_lines(path)
    p = dict(voices=16, drive="split", tick_hz=10000)
    tick = [firmware_metric(rows, m, **p) for m in ("instructions_per_tick", "instructions_per_tick_max")]
    plan = [firmware_metric(rows, m, **p) for m in ("instructions_per_plan", "instructions_per_plan_max")]
    worst_ms = firmware_metric(rows, "instructions_per_ms_worst", **p)
    return ["| 16 voices | mean | max |", "|---|---|---|",
            f"| 10 kHz tick (voices, reports, render: compensation and duties) | {thousands(tick[0])} | **{thousands(tick[1])}** |",
            f"| plan (pose, sensing, 3 QPs), once a ms | {thousands(plan[0])} | {thousands(plan[1])} |",
            f"| per ms: 10 ticks + 1 plan | {thousands(10 * tick[0] + plan[0])} | **{thousands(worst_ms)}** "
            "(every tick at its max and the worst plan) |"]


def work_precision(path):
    spec = importlib.util.spec_from_file_location("wp", os.path.join(ROOT, "tools/bench/sim_work_precision_table.py"))
    wp = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(wp)
    lines, _ = wp.render([r["params"] for r in json_lines(path)])
    return lines


def soak(path):
    """One row per soak summary (scripts/soak's JSON) in the folder or file."""
    files = sorted(os.path.join(path, f) for f in os.listdir(path) if f.endswith(".json")) if os.path.isdir(path) else [path]
    out = ["| device | minutes | load | card buffer | songs | music | notes started | late (max ticks) | lost / rejected | "
           "underruns | RSS start → end, growth | fds | CPU per music second | goals |", "|---" * 14 + "|"]
    for f in files:
        with open(f) as h:
            r = json.load(h)
        rss = r.get("rss_kib") or [[0, 0]]
        growth = r.get("rss_growth_kib_per_hour")
        fds = [v for _, v in (r.get("fds") or [])[1:]]  # the first sample is taken before hmp opened anything
        failed = [k for k, v in (r.get("goals") or {}).items() if v is False]
        out.append(" | ".join([
            f"| {r['device']}", f"{r['minutes']:g}", "stress-ng" if r.get("load") else "none",
            f"{r.get('audio_buffer_ms') or 21:g} ms",  # summaries before --audio-buffer-ms: hmp's default
            f"{r.get('songs_played')} ({r.get('files_skipped')} files skipped)", f"{r.get('music_s', 0):,.0f} s",
            f"{r.get('notes_started'):,}", f"{r.get('notes_late')} ({r.get('late_max_ticks')})",
            f"{r.get('notes_lost')} / {r.get('notes_rejected')}", f"{r.get('audio_underruns')}",
            f"{rss[1][1] / 1024 if len(rss) > 1 else 0:.1f} → {rss[-1][1] / 1024:.1f} MiB, "
            + (f"{growth / 1024:+.2f} MiB/h" if growth is not None else "not judged")
            + (" between songs" if r.get("rss_growth_from") == "between_songs" else ""),
            f"{min(fds)}–{max(fds)}" if fds else "—", f"{r.get('cpu_s_per_music_s') or 0:.3f} s",
            "all met" if r.get("pass") else "missed: " + ", ".join(failed)]) + " |")
    return out


RENDERERS = {"firmware-tick-voices": firmware_voices, "firmware-tick-drive": firmware_drive,
             "firmware-tick-split": firmware_split, "sim-work-precision": work_precision, "soak": soak}


def main(argv):
    if len(argv) < 2 or argv[1] not in ("--check", "--write"):
        print("usage: tools/bench/doc_tables.py --check|--write [DOC]", file=sys.stderr)
        return 2
    doc = argv[2] if len(argv) > 2 else os.path.join(ROOT, "docs/performance.md")
    with open(doc) as f:
        text = f.read()
    stale = []

    def replace(m):
        name, data = m.group(2), m.group(3)
        if name not in RENDERERS:
            raise SystemExit(f"{doc}: unknown generated table '{name}'")
        table = "\n".join(RENDERERS[name](os.path.join(ROOT, data))) + "\n"
        if table != m.group(4):
            stale.append(f"{name} (from {data})")
        return m.group(1) + table + m.group(5)

    new = BLOCK.sub(replace, text)
    if argv[1] == "--write":
        if new != text:
            with open(doc, "w") as f:
                f.write(new)
        return 0
    for s in stale:
        print(f"{os.path.relpath(doc, ROOT)}: the table {s} is not what its data gives: "
              "run tools/bench/doc_tables.py --write", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
