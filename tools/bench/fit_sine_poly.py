#!/usr/bin/env python3
"""Derives the coefficients of sine_poly() (shared/synth/sine.cpp).

sin(pi/2 * x) on x in [-1, 1] (one quarter turn either side of zero, after quadrant folding) is
approximated by an odd polynomial c1 x + c3 x^3 + ... chosen to minimise the maximum absolute error
(Remez exchange on [0, 1]; odd symmetry covers [-1, 0]). Plain Python floats (double) are ample for
errors around 1e-7. The coefficients are then rounded to float32, as the firmware stores them, and the
error is re-measured with the rounded values.

Usage: tools/bench/fit_sine_poly.py [TERMS]   (default 4 terms: degree 7)
"""
import math
import sys

from polyfit_common import f32, solve


def target(x):
    return math.sin(math.pi / 2 * x)


def poly(c, x):
    return sum(ck * x ** (2 * k + 1) for k, ck in enumerate(c))


def local_extrema(c, grid):
    """Points of the grid where |error| has a local maximum, with the error's sign."""
    err = [poly(c, x) - target(x) for x in grid]
    found = []
    for i in range(1, len(grid)):
        left = err[i - 1]
        right = err[i + 1] if i + 1 < len(grid) else -math.inf * (1 if err[i] > 0 else -1)
        if abs(err[i]) >= abs(left) and (i + 1 == len(grid) or abs(err[i]) >= abs(right)):
            found.append((grid[i], err[i]))
    return found


def alternating(points, count):
    """Largest-|error| point of every run of equal sign, then the `count` biggest contiguous ones."""
    runs = []
    for x, e in points:
        if runs and (runs[-1][1] > 0) == (e > 0):
            if abs(e) > abs(runs[-1][1]):
                runs[-1] = (x, e)
        else:
            runs.append((x, e))
    while len(runs) > count:  # drop the smaller end
        runs.pop(0 if abs(runs[0][1]) < abs(runs[-1][1]) else -1)
    return [x for x, _ in runs]


def remez(terms, iterations=30):
    ref = [math.sin(math.pi / 2 * (i + 1) / (terms + 1)) for i in range(terms + 1)]
    grid = [i / 200000 for i in range(200001)]
    c = []
    for _ in range(iterations):
        rows = [[x ** (2 * k + 1) for k in range(terms)] + [(-1) ** i] for i, x in enumerate(ref)]
        sol = solve(rows, [target(x) for x in ref])
        c = sol[:terms]
        ext = local_extrema(c, grid)
        new_ref = alternating(ext, terms + 1)
        if len(new_ref) != terms + 1 or new_ref == ref:
            break
        ref = new_ref
    return c


def max_error(c):
    return max(abs(poly(c, i / 1000000) - target(i / 1000000)) for i in range(1000001))


def main():
    terms = int(sys.argv[1]) if len(sys.argv) > 1 else 4
    c = remez(terms)
    c32 = [f32(v) for v in c]
    print(f"# {terms} terms: max |error| {max_error(c):.3e} (double coefficients), "
          f"{max_error(c32):.3e} (float32 coefficients)")
    for k, v in enumerate(c32):
        print(f"c{2 * k + 1} = {v:.9e}f")


if __name__ == "__main__":
    main()
