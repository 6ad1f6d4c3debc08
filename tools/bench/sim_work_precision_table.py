#!/usr/bin/env python3
"""The tables of docs/performance.md, "Plant simulator: work-precision", from the JSON lines of
`scripts/bench sim-work-precision` (stdin): the default integrator in every scene at every stiffness
against the goals (the string force's error below 1 kHz in brackets beside it), its errors over one tick
(where resolved by their own reference), and how much CPU CVODE needs for the default's finger-force error.

Usage: scripts/bench sim-work-precision | python3 tools/bench/sim_work_precision_table.py
"""
import json
import math
import sys

TAUT_GOAL = (0.01, 0.005)   # string force, finger force: the taut scenes, at >= 50x real time
SLACK_GOAL = (0.02, 0.01)   # slack and saturation scenes at 10^3-10^5 N/m (no speed goal)
REALTIME_GOAL = 50.0


def pct(x):
    if x is None or not math.isfinite(x):
        return "—"
    if x >= 0.001:
        return f"{100 * x:.2f}%"
    return f"{100 * x:.1e}%".replace("e-0", "e-")


def cvode_cpu_at(points, error):
    """CPU seconds per simulated second CVODE needs for this finger-force error (log-log interpolation
    between its tolerances; None if its curve does not reach the error)."""
    curve = sorted((p["finger_force_error_rel"], 1 / p["realtime_factor"]) for p in points
                   if p["ok"] and p["finger_force_error_rel"] > 0)
    for (e0, c0), (e1, c1) in zip(curve, curve[1:]):
        if e0 <= error <= e1:
            t = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0)) if e1 > e0 else 0
            return math.exp(math.log(c0) + t * (math.log(c1) - math.log(c0)))
    if curve and error <= curve[0][0]:
        return curve[0][1]  # more accurate than CVODE's tightest: at least its cost
    return None


def one_tick(row):
    """The errors over one tick, string / finger force, if measured and ten times their reference's
    convergence; else None."""
    s, f = row.get("tick_force_error_rel"), row.get("tick_finger_force_error_rel")
    cs, cf = row.get("tick_reference_convergence_force"), row.get("tick_reference_convergence")
    if None in (s, f, cs, cf) or s < 10 * cs or f < 10 * cf:
        return None
    return f"{pct(s)} / {pct(f)}"


def render(rows):
    """The table (Markdown lines) and the cells that miss a goal, from the benchmark's rows' params."""
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    stiffnesses = sorted({r["stiffness_n_per_m"] for r in rows})
    lines = ["| scene | " + " | ".join(f"{k:.0e} N/m" for k in stiffnesses) + " |",
             "|---|" + "---|" * len(stiffnesses)]
    misses = []
    for scene in scenes:
        cells = []
        for k in stiffnesses:
            cell = [r for r in rows if r["scene"] == scene and r["stiffness_n_per_m"] == k]
            default = next((r for r in cell if r["default"]), None)
            if default is None:
                cells.append("—")
                continue
            taut = not scene.startswith(("slack", "saturation"))
            goal = TAUT_GOAL if taut else (SLACK_GOAL if k <= 1e5 else None)
            s, f, rt = default["force_error_rel"], default["finger_force_error_rel"], default["realtime_factor"]
            claimed = default["claimed"]
            band = default.get("band_force_error_rel")
            band_text = f" (< 1 kHz {pct(band)})" if band is not None and claimed else ""
            text = f"{pct(s)}{band_text} / {pct(f)}, {rt:.0f}×" if claimed else \
                f"unresolved (reference {default['reference_convergence_force']:.1g}), {rt:.0f}×"
            ok = claimed and goal is not None and s <= goal[0] and f <= goal[1] and (not taut or rt >= REALTIME_GOAL)
            if goal is not None and not ok:
                text = f"**{text}**"
                misses.append(f"{scene} at {k:.0e}")
            cvode = cvode_cpu_at([r for r in cell if r["integrator"] == "cvode"], f)
            if cvode is not None and rt > 0:
                text += f" (CVODE {cvode * rt:.0f}× the CPU)"
            tick = one_tick(default)
            if tick:
                text += f"; one tick {tick}"
            cells.append(text)
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")
    return lines, misses


def main():
    lines, misses = render([json.loads(line)["params"] for line in sys.stdin if line.startswith("{")])
    print("\n".join(lines))
    print()
    print("bold: a goal missed (" + (", ".join(misses) if misses else "none") + ")")


if __name__ == "__main__":
    main()
