#pragma once
// The matrix exponential for the exact discretisation of the drive's small linear models: a model's
// inputs and output integrals are appended as extra states, and the exponential of the augmented matrix
// over one tick holds the whole update (the firmware drive's models, firmware/drive_model.cpp). Scaling
// and squaring with a Taylor series: computed once at start-up, never in the tick. The scalar is a
// parameter: the drive computes its models in double (its stiff strings give A·h entries of thousands and
// output integrals that cancel to a few parts in 10⁶), and keeps only the float results for the tick.
namespace hmp::spidar {

// e^{A h} by scaling and squaring with a Taylor series: 12 terms in float, 18 in double, after halving
// A·h until its norm is ≤ 1/2 (the truncation is then below the scalar's precision). `out` must not be `a`.
template <class T, int N>
void expm(const T (&a)[N][N], T h, T (&out)[N][N]) {
  constexpr int kTerms = sizeof(T) > sizeof(float) ? 18 : 12;
  T m[N][N]{};
  T norm = 0;
  for (int i = 0; i < N; ++i) {
    T row = 0;
    for (int j = 0; j < N; ++j) {
      m[i][j] = a[i][j] * h;
      row += m[i][j] >= 0 ? m[i][j] : -m[i][j];
    }
    if (row > norm) norm = row;
  }
  int squarings = 0;
  while (norm > static_cast<T>(0.5) && squarings < 60) {
    norm *= static_cast<T>(0.5);
    ++squarings;
  }
  T scale = 1;
  for (int s = 0; s < squarings; ++s) scale *= static_cast<T>(0.5);
  for (auto& row : m)
    for (T& v : row) v *= scale;
  // Horner: I + m(I + m/2(I + m/3(…))), accumulated in `out`; `next` is the one scratch matrix.
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) out[i][j] = i == j ? T(1) : T(0);
  T next[N][N];
  for (int k = kTerms; k >= 1; --k) {
    const T inv_k = T(1) / static_cast<T>(k);
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        T s = 0;
        for (int l = 0; l < N; ++l) s += m[i][l] * out[l][j];
        next[i][j] = (i == j ? T(1) : T(0)) + s * inv_k;
      }
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) out[i][j] = next[i][j];
  }
  for (int s = 0; s < squarings; ++s) {
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        T acc = 0;
        for (int l = 0; l < N; ++l) acc += out[i][l] * out[l][j];
        next[i][j] = acc;
      }
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) out[i][j] = next[i][j];
  }
}

}  // namespace hmp::spidar
