#pragma once
// In-place Cholesky factorisation and solves for the small symmetric positive definite systems of the
// SPIDAR code (≤ 8×8 tension subsystems, the 6×6 pose normal equations). Only the lower triangle of `a`
// is read. One square root and one division per pivot; everything else is multiply-adds.
#include <cmath>

namespace hmp::spidar {

// a = L Lᵀ: L overwrites the lower triangle, its diagonal stored inverted so that solves only multiply.
// Returns false — leaving `a` unusable — when a pivot is not above `tiny` (numerically singular, or NaN).
template <class T, int N>
bool cholesky_factor(T (&a)[N][N], int n, T tiny) {
  for (int k = 0; k < n; ++k) {
    T pivot = a[k][k];
    for (int j = 0; j < k; ++j) pivot -= a[k][j] * a[k][j];
    if (!(pivot > tiny)) return false;
    const T inv = static_cast<T>(1) / std::sqrt(pivot);
    a[k][k] = inv;
    for (int i = k + 1; i < n; ++i) {
      T s = a[i][k];
      for (int j = 0; j < k; ++j) s -= a[i][j] * a[k][j];
      a[i][k] = s * inv;
    }
  }
  return true;
}

// Solves L Lᵀ x = b in place of b, with `l` from cholesky_factor.
template <class T, int N>
void cholesky_solve(const T (&l)[N][N], int n, T (&b)[N]) {
  for (int i = 0; i < n; ++i) {
    T s = b[i];
    for (int j = 0; j < i; ++j) s -= l[i][j] * b[j];
    b[i] = s * l[i][i];
  }
  for (int i = n - 1; i >= 0; --i) {
    T s = b[i];
    for (int j = i + 1; j < n; ++j) s -= l[j][i] * b[j];
    b[i] = s * l[i][i];
  }
}

// Full-size versions: the size is a compile-time constant, so the compiler can unroll the loops (the pose's
// 6×6 normal equations).
template <class T, int N>
bool cholesky_factor(T (&a)[N][N], T tiny) {
  return cholesky_factor(a, N, tiny);
}
template <class T, int N>
void cholesky_solve(const T (&l)[N][N], T (&b)[N]) {
  cholesky_solve(l, N, b);
}

}  // namespace hmp::spidar
