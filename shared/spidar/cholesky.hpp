#pragma once
// In-place Cholesky factorisation and solve for the small symmetric positive definite systems of the
// SPIDAR code (≤ 8×8 tension subsystems, the 6×6 pose normal equations). Only the lower triangle of `a`
// is read. One square root and one division per pivot; everything else is multiply-adds.
#include <cmath>

namespace hmp::spidar {

// Factors a = L Lᵀ (L overwrites the lower triangle, its diagonal stored inverted so the solve multiplies)
// and solves a x = b in place of b. Returns false — leaving `a` and `b` unusable — when a pivot is not
// above `tiny` (numerically singular or non-finite input).
template <class T, int N>
bool cholesky_solve(T (&a)[N][N], int n, T (&b)[N], T tiny) {
  for (int k = 0; k < n; ++k) {
    T pivot = a[k][k];
    for (int j = 0; j < k; ++j) pivot -= a[k][j] * a[k][j];
    if (!(pivot > tiny)) return false;  // also catches NaN
    const T inv = static_cast<T>(1) / std::sqrt(pivot);
    a[k][k] = inv;
    for (int i = k + 1; i < n; ++i) {
      T s = a[i][k];
      for (int j = 0; j < k; ++j) s -= a[i][j] * a[k][j];
      a[i][k] = s * inv;
    }
  }
  for (int i = 0; i < n; ++i) {  // L y = b
    T s = b[i];
    for (int j = 0; j < i; ++j) s -= a[i][j] * b[j];
    b[i] = s * a[i][i];
  }
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = y
    T s = b[i];
    for (int j = i + 1; j < n; ++j) s -= a[j][i] * b[j];
    b[i] = s * a[i][i];
  }
  return true;
}

}  // namespace hmp::spidar
