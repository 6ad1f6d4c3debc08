#!/usr/bin/env python3
"""Writes examples/pedal-demo.mid: a short piano phrase played twice, first with the sustain pedal held
down through it (pressed at 0 s, lifted at 2 s), then without (from 2.5 s). For `--pedal` (docs/player.md)
and its plots (scripts/doc-plots). 500 ticks a quarter at 120 bpm: a tick is a millisecond."""
import sys

from smf_bytes import header, meta, track_chunk, vlq


def track(events):
    return track_chunk(b"".join(vlq(delta) + bytes(data) for delta, data in events) + vlq(0) + meta(0x2F, b""))


def main(path):
    name = b"pedal demo"
    conductor = [(0, [0xFF, 0x51, 3, 0x07, 0xA1, 0x20]), (0, [0xFF, 0x03, len(name)] + list(name))]
    piano = [(0, [0xFF, 0x03, 5] + list(b"piano")), (0, [0xC0, 0]), (0, [0xB0, 64, 127])]
    keys = [60, 64, 67, 72]
    at = 0  # ms of the last event
    events = []  # (time, bytes)
    for phrase, start in enumerate((250, 2750)):
        for i, key in enumerate(keys):
            t = start + 300 * i
            events += [(t, [0x90, key, 90]), (t + 150, [0x80, key, 0])]  # staccato: 150 ms
        if phrase == 0:
            events.append((2000, [0xB0, 64, 0]))  # the pedal lifts
    events.sort(key=lambda e: e[0])
    for t, data in events:
        piano.append((t - at, data))
        at = t
    with open(path, "wb") as f:
        f.write(header(1, 2, 500))
        f.write(track(conductor) + track(piano))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "examples/pedal-demo.mid")
