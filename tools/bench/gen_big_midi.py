#!/usr/bin/env python3
"""Writes the large Standard MIDI File of the midi-parse benchmark (python3 standard library only).

A format 1 file at 480 ticks per quarter: a conductor track (tempo changes every few bars, time
signatures, markers) and 11 instrument tracks on their own channels (drums on channel 10), each with a
name, a program change, volume/expression/sustain controllers and pitch bends besides its notes. Chords
and re-struck keys make notes overlap on the same key (pairing is first in, first out). Channel messages
use running status; notes end with note-on velocity 0 (running status) in most tracks and with explicit
note-off (0x8n) in some. The same arguments always give the same bytes (fixed random seed).

Usage: gen_big_midi.py OUTPUT [--notes N]   (default 560000 notes, about 5.3 MB)
"""
import argparse
import os
import random
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from smf_bytes import header, meta, track_chunk, vlq  # noqa: E402 (tools/ is not a package)

TPQ = 480


def encode_track(events):
    """events: (tick, order, payload) with payload = bytes of one event, its status byte first.
    Sorted by tick then order (note-offs use order 0, so they come before note-ons at one tick)."""
    events.sort(key=lambda e: (e[0], e[1]))
    out = bytearray()
    last_tick = 0
    running = None
    for tick, _, payload in events:
        out += vlq(tick - last_tick)
        last_tick = tick
        status = payload[0]
        if status < 0xF0:
            # Running status: the status byte is left out when it repeats.
            out += payload[1:] if status == running else payload
            running = status
        else:
            out += payload
            running = None  # the writer restates the status after a meta event (readers differ there)
    out += vlq(0) + meta(0x2F, b"")
    return track_chunk(out)


def conductor(rng, end_tick):
    events = [(0, 1, meta(0x03, b"Conductor")), (0, 1, meta(0x58, bytes([4, 2, 24, 8])))]
    tick, bar = 0, 0
    while tick < end_tick:
        events.append((tick, 1, meta(0x51, struct.pack(">I", rng.randint(300000, 1000000))[1:])))
        if bar % 16 == 0:
            events.append((tick, 1, meta(0x06, b"Section %d" % (bar // 16))))
            numerator = rng.choice([3, 4, 4, 6])
            events.append((tick, 1, meta(0x58, bytes([numerator, 2, 24, 8]))))
        bars = rng.randint(1, 4)
        tick += bars * 4 * TPQ
        bar += bars
    return events


def instrument(rng, channel, program, name, notes, explicit_off):
    events = [(0, 1, meta(0x03, name.encode())),
              (0, 1, bytes([0xC0 | channel, program])),
              (0, 1, bytes([0xB0 | channel, 7, rng.randint(80, 120)]))]
    low = 35 if channel == 9 else rng.randint(28, 60)
    high = 81 if channel == 9 else low + rng.randint(12, 36)
    tick, made = 0, 0
    while made < notes:
        # A chord (1–4 keys) or a single note, sometimes re-striking a key that is still sounding.
        size = min(notes - made, rng.choice([1, 1, 1, 2, 3, 4]))
        for _ in range(size):
            key = rng.randint(low, high)
            length = rng.choice([60, 120, 240, 240, 480, 960]) + rng.randint(-10, 10)
            events.append((tick, 2, bytes([0x90 | channel, key, rng.randint(30, 127)])))
            off = bytes([0x80 | channel, key, 64]) if explicit_off else bytes([0x90 | channel, key, 0])
            events.append((tick + length, 0, off))
        made += size
        if rng.random() < 0.25:  # an expression swell: a few steps of controller 11
            level = rng.randint(40, 100)
            for step in range(4):
                events.append((tick + step * 30, 1, bytes([0xB0 | channel, 11, min(127, level + 8 * step)])))
        if rng.random() < 0.02:
            events.append((tick, 1, bytes([0xB0 | channel, 64, rng.choice([0, 127])])))  # sustain pedal
        if channel != 9 and rng.random() < 0.03:
            for step in range(4):  # a short bend and back
                bend = 8192 + (4 - abs(2 - step) * 2) * 300
                events.append((tick + step * 20, 1, bytes([0xE0 | channel, bend & 0x7F, bend >> 7])))
        tick += rng.choice([0, 60, 120, 120, 240, 480])
    return events, tick + 960


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("output")
    ap.add_argument("--notes", type=int, default=560000)
    args = ap.parse_args()
    rng = random.Random(20240611)
    parts = [(0, 73, "Flute", False), (1, 40, "Violin I", True), (2, 40, "Violin II", False),
             (3, 41, "Viola", True), (4, 42, "Cello", True), (5, 43, "Contrabass", False),
             (6, 6, "Harpsichord RH", True), (7, 6, "Harpsichord LH", False), (8, 0, "Piano", True),
             (9, 0, "Drums", False), (10, 48, "Strings", False)]
    per_track = args.notes // len(parts)
    tracks, end_tick = [], 0
    for i, (channel, program, name, explicit_off) in enumerate(parts):
        count = per_track + (args.notes - per_track * len(parts) if i == 0 else 0)
        events, end = instrument(rng, channel, program, name, count, explicit_off)
        tracks.append(encode_track(events))
        end_tick = max(end_tick, end)
    tracks.insert(0, encode_track(conductor(rng, end_tick)))
    head = header(1, len(tracks), TPQ)
    with open(args.output, "wb") as f:
        f.write(head)
        for t in tracks:
            f.write(t)


if __name__ == "__main__":
    main()
