#!/usr/bin/env python3
"""Derives the coefficients of envelope::detail::release_exp2() (shared/envelope/envelope.hpp).

The release of an envelope needs 2^x (x <= 0) for every sounding voice on every tick. After splitting
x = i + f with i the nearest integer, 2^f on f in [-1/2, 1/2] is approximated by
    p(f) = 1 + c1 f + c2 f^2 + ... + c6 f^6
with the constant term fixed at exactly 1 (so that 2^0 is exactly 1: a release starts exactly at the
sustain level). The coefficients minimise the maximum *relative* error (2^i only scales it), found by
Lawson's iteratively reweighted least squares on a dense grid; plain Python floats (double) are ample.
They are then rounded to float32, as the firmware stores them, and the error is re-measured with the
polynomial evaluated in float32 (Horner, one rounding per step).

Usage: tools/bench/firmware-tick-exp2-fit.py [DEGREE]   (default 6)
"""
import sys

from polyfit_common import f32, solve


def fit(degree, points=4001, rounds=200):
    grid = [-0.5 + i / (points - 1) for i in range(points)]
    weights = [1.0] * points
    for _ in range(rounds):
        # Weighted least squares on the relative error (p(f) - 2^f) / 2^f, unknowns c1..cN.
        a = [[0.0] * degree for _ in range(degree)]
        b = [0.0] * degree
        for f, w in zip(grid, weights):
            t = 2.0 ** f
            row = [f ** k / t for k in range(1, degree + 1)]
            y = (t - 1.0) / t
            for i in range(degree):
                b[i] += w * row[i] * y
                for j in range(degree):
                    a[i][j] += w * row[i] * row[j]
        c = solve(a, b)
        err = [abs(1.0 + sum(c[k - 1] * f ** k for k in range(1, degree + 1)) - 2.0 ** f) / 2.0 ** f for f in grid]
        total = sum(w * e for w, e in zip(weights, err))
        weights = [w * e / total * points for w, e in zip(weights, err)]  # Lawson's update
    return c, max(err), grid


def main():
    degree = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    c, exact_err, grid = fit(degree)
    cf = [f32(x) for x in c]

    def horner(f):
        acc = cf[-1]
        for k in range(degree - 2, -1, -1):
            acc = f32(f32(acc * f) + cf[k])
        return f32(f32(acc * f) + 1.0)

    float_err = max(abs(horner(f32(f)) - 2.0 ** f32(f)) / 2.0 ** f32(f) for f in grid)
    print(f"degree {degree}: max relative error {exact_err:.2e} (exact), {float_err:.2e} "
          f"= {float_err / 2 ** -23:.2f} ulp (float32 coefficients, float32 Horner)")
    for k, x in enumerate(cf, 1):
        print(f"c{k} = {x:.9e}f")


if __name__ == "__main__":
    main()
