"""The bytes of Standard MIDI Files, for the project's generators (tools/make_pedal_example.py,
tools/bench/gen_big_midi.py): variable-length quantities, meta events, the header and track chunks."""
import struct


def vlq(value):
    """A variable-length quantity: 7 bits a byte, most significant first, the high bit on all but the last."""
    out = [value & 0x7F]
    value >>= 7
    while value:
        out.append(0x80 | (value & 0x7F))
        value >>= 7
    return bytes(reversed(out))


def meta(kind, body):
    return b"\xff" + bytes([kind]) + vlq(len(body)) + body


def header(file_format, tracks, division):
    return b"MThd" + struct.pack(">IHHH", 6, file_format, tracks, division)


def track_chunk(body):
    return b"MTrk" + struct.pack(">I", len(body)) + bytes(body)
