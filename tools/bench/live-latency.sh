#!/usr/bin/env bash
# live-latency (docs/live.md): `hmp live` from a JACK MIDI event to the device's Started report for its
# note, by stage, over LIVE_NOTES note-ons (default 2000, one every LIVE_SPACING_MS, default 8 ms, each
# released a JACK cycle later), on the simulated device and on the QEMU board (over its UART and over its
# Ethernet link) when its image and qemu-system-arm are there. A JACK server of its own with the dummy
# back-end (no sound hardware): LIVE_JACK_PERIOD frames (default 64) at 48 kHz.
set -euo pipefail
build=$1
cmake --build "$build" -j2 --target hmp bench_live_latency >&2
tmp=$(mktemp -d)
export JACK_DEFAULT_SERVER="hmp-bench-$$" JACK_NO_AUDIO_RESERVATION=1
jackd -n "$JACK_DEFAULT_SERVER" -d dummy -r 48000 -p "${LIVE_JACK_PERIOD:-64}" >"$tmp/jackd.log" 2>&1 &
jackd_pid=$!
trap 'kill $jackd_pid 2>/dev/null; wait $jackd_pid 2>/dev/null; rm -rf "$tmp"' EXIT
sleep 1
notes=${LIVE_NOTES:-2000}
spacing=${LIVE_SPACING_MS:-8}
"$build/bench/bench_live_latency" sim "$notes" "$build/bin/hmp" "$tmp/sim.jsonl" "$spacing"
image=${HMP_QEMU_ELF:-$(ls "$(dirname "$build")"/qemu-an386/boards/qemu-an386/hmp_fw_qemu_an386-*.elf 2>/dev/null | tail -1 || true)}
if [ -f "$image" ] && command -v "${QEMU_SYSTEM_ARM:-qemu-system-arm}" >/dev/null; then
  # The board's two links: its UART (a byte per emulator round trip) and its Ethernet controller.
  for device in qemu qemu:net; do
    HMP_QEMU_ELF=$image "$build/bench/bench_live_latency" "$device" "$notes" "$build/bin/hmp" "$tmp/qemu.jsonl" "$spacing"
  done
else
  echo "live-latency: no QEMU image at $image: qemu part skipped" >&2
fi
