"""Helpers shared by the coefficient-fitting scripts (fit_sine_poly.py, firmware-tick-exp2-fit.py):
float32 rounding, as the firmware stores its coefficients, and a small dense linear solver."""
import struct


def f32(x):
    """x rounded to the nearest float32."""
    return struct.unpack('f', struct.pack('f', x))[0]


def solve(a, b):
    """Gaussian elimination with partial pivoting (small dense system)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(m[r][col]))
        m[col], m[piv] = m[piv], m[col]
        for r in range(col + 1, n):
            f = m[r][col] / m[col][col]
            for k in range(col, n + 1):
                m[r][k] -= f * m[col][k]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x
