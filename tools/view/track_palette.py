#!/usr/bin/env python3
"""Chooses the window's sixteen track colours (host/view/palette.hpp).

Candidates: the sRGB grid of steps 0.1. Each is taken as drawn, dimmed towards the background by
kBehindStrength, and must be at least MIN_LIGHTNESS in L* and MIN_CHROMA in C*ab and at least
MIN_FROM_FIXED from the fixed colours (felt blue, sounding yellow, white, background) under normal vision.
Then greedy farthest-point selection: each pick maximises its smallest CIE76 distance to the fixed colours
and the picks so far, the smallest over normal vision and simulated protanopia, deuteranopia and
tritanopia (Machado, Oliveira and Fernandes 2009, severity 1, on linear RGB). Prints the table for
palette.hpp and the smallest distance reached.

Usage: tools/view/track_palette.py
"""
import itertools
import math

BACKGROUND = (0.07, 0.07, 0.08)
FELT_BLUE = (30, 136, 229)
SOUNDING_YELLOW = (240, 228, 66)
WHITE = (255, 255, 255)
BEHIND_STRENGTH = 0.7
MIN_LIGHTNESS, MIN_CHROMA, MIN_FROM_FIXED = 35.0, 25.0, 25.0
COUNT = 16

VISION = {
    "normal": ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    "protanopia": ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216),
                   (-0.003882, -0.048116, 1.051998)),
    "deuteranopia": ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413),
                     (-0.011820, 0.042940, 0.968881)),
    "tritanopia": ((1.255528, -0.076749, -0.178779), (-0.078411, 0.930809, 0.147602),
                   (0.004733, 0.691367, 0.303900)),
}


def to_linear(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def lab(rgb, matrix):
    """CIELAB (D65) of an sRGB colour (0–1) as seen through a vision matrix."""
    lin = [to_linear(c) for c in rgb]
    s = [min(1.0, max(0.0, sum(matrix[i][j] * lin[j] for j in range(3)))) for i in range(3)]
    x = 0.4124564 * s[0] + 0.3575761 * s[1] + 0.1804375 * s[2]
    y = 0.2126729 * s[0] + 0.7151522 * s[1] + 0.0721750 * s[2]
    z = 0.0193339 * s[0] + 0.1191920 * s[1] + 0.9503041 * s[2]

    def f(t):
        return t ** (1 / 3) if t > 216 / 24389 else (24389 / 27 * t + 16) / 116

    fx, fy, fz = f(x / 0.95047), f(y), f(z / 1.08883)
    return (116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz))


def behind(rgb):
    return tuple(BACKGROUND[i] + BEHIND_STRENGTH * (rgb[i] - BACKGROUND[i]) for i in range(3))


def main():
    fixed = [tuple(c / 255 for c in FELT_BLUE), tuple(c / 255 for c in SOUNDING_YELLOW),
             tuple(c / 255 for c in WHITE), BACKGROUND]
    steps = [i / 10 for i in range(11)]
    candidates = list(itertools.product(steps, repeat=3))
    seen = {v: [lab(behind(c), m) for c in candidates] for v, m in VISION.items()}
    fixed_seen = {v: [lab(c, m) for c in fixed] for v, m in VISION.items()}

    def allowed(i):
        l, a, b = seen["normal"][i]
        if l < MIN_LIGHTNESS or math.hypot(a, b) < MIN_CHROMA:
            return False
        return min(math.dist(seen["normal"][i], f) for f in fixed_seen["normal"]) >= MIN_FROM_FIXED

    nearest = [min(math.dist(seen[v][i], f) for v in VISION for f in fixed_seen[v]) if allowed(i) else -1.0
               for i in range(len(candidates))]
    picks = []
    for _ in range(COUNT):
        best = max(range(len(candidates)), key=lambda i: nearest[i])
        picks.append(best)
        for j in range(len(candidates)):
            if nearest[j] >= 0:
                nearest[j] = min(nearest[j], min(math.dist(seen[v][best], seen[v][j]) for v in VISION))
    closest = min(math.dist(p, q) for v in VISION
                  for p, q in itertools.combinations([seen[v][i] for i in picks] + fixed_seen[v], 2))
    rows = [", ".join("rgb8({}, {}, {})".format(*(round(c * 255) for c in candidates[i])) for i in picks[k:k + 4])
            for k in range(0, COUNT, 4)]
    print("inline constexpr std::array<Rgb, {}> kTrackColours{{{{\n    {},\n}}}};".format(COUNT, ",\n    ".join(rows)))
    print("// smallest ΔE*ab over the four visions: {:.2f}".format(closest))


if __name__ == "__main__":
    main()
