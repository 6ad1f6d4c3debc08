#!/usr/bin/env bash
# e2e-timing (design §10): `hmp play` end to end.
#   - onset error (actual − scheduled tick, from --log) over the whole demo song on the simulated
#     device, and over a passage on the QEMU board when its image and qemu-system-arm are there;
#   - host CPU of the hmp process while playing with --no-audio (utime + stime from /proc, over the
#     wall time): on sim it includes the simulated device's 1 kHz thread, on qemu it is the player alone
#     (the emulator is another process);
#   - the clock-sync error against the simulated device's own tick counter (bench_e2e_timing);
#   - the audio-haptic skew of every note, measured end to end with the player's real audio path on a
#     simulated sound card (bench_audio_haptic_skew; E2E_SKEW_NOTES notes, default 60, 1.5 s each).
# Run by scripts/bench with the build directory as $1. E2E_SECONDS limits the sim run (default: the
# whole song, 310 s); E2E_QEMU_SECONDS the QEMU passage (default 60); E2E_SYNC_SECONDS the clock run (60).
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target hmp bench_e2e_timing bench_audio_haptic_skew >&2
song=examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid
hmp="$build/bin/hmp"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# play DEVICE SECONDS: runs hmp, prints JSON lines for the onset errors and the CPU use.
play() {
  local device=$1 seconds=$2
  local window=()
  [ "$seconds" != "song" ] && window=(--to "$seconds")
  python3 - "$hmp" "$song" "$device" "$tmp/$device.jsonl" "$seconds" "${window[@]}" <<'PY'
import json, os, subprocess, sys, time
hmp, song, device, log, seconds, *window = sys.argv[1:]
tck = os.sysconf("SC_CLK_TCK")
start = time.monotonic()
p = subprocess.Popen([hmp, "play", song, "--track", "flute", "--no-audio", "--device", device, "--log", log, *window],
                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
cpu = 0.0
while p.poll() is None:
    try:
        with open(f"/proc/{p.pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        cpu = (int(fields[11]) + int(fields[12])) / tck  # utime, stime of hmp itself
    except (OSError, IndexError, ValueError):
        pass
    time.sleep(0.2)
wall = time.monotonic() - start
err = p.stderr.read().decode()
if p.returncode != 0:
    sys.exit(f"hmp play --device {device} failed: {err.strip()}")
notes = [json.loads(l) for l in open(log) if '"track"' in l]
errors = sorted(n["actual_tick"] - n["scheduled_tick"] for n in notes)
summary = [json.loads(l)["summary"] for l in open(log) if '"summary"' in l][0]
params = {"device": device, "track": "flute", "seconds": 310 if seconds == "song" else float(seconds), "notes": len(notes)}
def emit(metric, value, unit, extra=None):
    line = {"bench": "e2e-timing", "metric": metric, "value": round(value, 4), "unit": unit, "params": {**params, **(extra or {})}}
    print(json.dumps(line, separators=(",", ":")), flush=True)
emit("onset_error_max", errors[-1] if errors else 0, "ticks")
emit("onset_error_mean", sum(errors) / len(errors) if errors else 0, "ticks")
emit("onset_error_p99", errors[int(0.99 * (len(errors) - 1))] if errors else 0, "ticks")
emit("onsets_exact", sum(1 for e in errors if e == 0) / len(errors) if errors else 0, "fraction")
emit("notes_played", summary["notes_played"], "notes", {"sent": summary["notes_sent"], "late": summary["late"], "rejected": summary["rejected"]})
emit("host_cpu", 100.0 * cpu / wall, "percent", {"cpu_s": round(cpu, 2), "wall_s": round(wall, 1),
     "includes": "player + simulated device" if device == "sim" else "player only"})
PY
}

play sim "${E2E_SECONDS:-song}"
image=${HMP_QEMU_ELF:-$(ls "$(dirname "$build")"/qemu-an386/boards/qemu-an386/hmp_fw_qemu_an386-*.elf 2>/dev/null | tail -1 || true)}
if [ -f "$image" ] && command -v "${QEMU_SYSTEM_ARM:-qemu-system-arm}" >/dev/null; then
  HMP_QEMU_ELF=$image play qemu "${E2E_QEMU_SECONDS:-60}"
else
  echo "e2e-timing: no QEMU image at $image: qemu part skipped" >&2
fi
"$build/bench/bench_e2e_timing" "$song" 1 "${E2E_SYNC_SECONDS:-60}"
"$build/bench/bench_audio_haptic_skew" "${E2E_SKEW_NOTES:-60}"
