#!/usr/bin/python3
"""The mido side of the midi-parse benchmark: parse a Standard MIDI File with mido and pair its notes.

Usage: mido_pairing.py FILE   (Debian's /usr/bin/python3 with python3-mido)

Prints one JSON object: {"seconds": parse + pairing time, "notes": paired notes}. Only the work is timed
(time.perf_counter around it), not the interpreter's start-up nor importing mido. Pairing is the same rule
as hmp's reader (design §4): per (track, channel, key) first in, first out; note-on with velocity 0 is a
note-off; a note still on at the end of its track ends there; note-offs with nothing to end are ignored.
It stays in ticks, as hmp's midi::load_song does (hmp computes a note's µs when asked); load_song also
builds the tempo map, each note's program and per-track statistics, so this still does less than hmp.
"""
import json
import sys
import time
from collections import deque

import mido


def parse_and_pair(path):
    song = mido.MidiFile(path)
    notes = []  # (track, channel, key, velocity, start_tick, end_tick)
    for index, track in enumerate(song.tracks):
        sounding = {}
        tick = 0
        for msg in track:
            tick += msg.time
            kind = msg.type
            if kind == "note_on" and msg.velocity > 0:
                sounding.setdefault((msg.channel, msg.note), deque()).append((msg.velocity, tick))
            elif kind == "note_off" or kind == "note_on":
                queue = sounding.get((msg.channel, msg.note))
                if queue:
                    velocity, start = queue.popleft()
                    notes.append((index, msg.channel, msg.note, velocity, start, tick))
        for (channel, key), queue in sounding.items():
            for velocity, start in queue:
                notes.append((index, channel, key, velocity, start, tick))
    return notes


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: mido_pairing.py FILE")
    start = time.perf_counter()
    notes = parse_and_pair(sys.argv[1])
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "notes": len(notes)}))


if __name__ == "__main__":
    main()
