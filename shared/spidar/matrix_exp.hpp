#pragma once
// The matrix exponential for the exact discretisation of the drive's small linear models: a model's
// inputs and output integrals are appended as extra states, and the exponential of the augmented matrix
// over one tick holds the whole update (the firmware drive's models, firmware/drive_model.cpp). Scaling and squaring with a Taylor
// series, in float: computed once at start-up, never in the tick. Callers scale their states so that the
// entries of A·h are of order one; then a few squarings and 12 terms keep it at float precision.
namespace hmp::spidar {

// e^{A h} by scaling and squaring with a 12-term Taylor series.
template <int N>
void expm(const float (&a)[N][N], float h, float (&out)[N][N]) {
  float m[N][N]{};
  float norm = 0.0f;
  for (int i = 0; i < N; ++i) {
    float row = 0.0f;
    for (int j = 0; j < N; ++j) {
      m[i][j] = a[i][j] * h;
      row += m[i][j] >= 0.0f ? m[i][j] : -m[i][j];
    }
    if (row > norm) norm = row;
  }
  // Halve until the norm is ≤ 1/2: the series then converges to float precision within 12 terms.
  int squarings = 0;
  while (norm > 0.5f && squarings < 40) {
    norm *= 0.5f;
    ++squarings;
  }
  const float scale = 1.0f / static_cast<float>(1ull << squarings);
  for (auto& row : m)
    for (float& v : row) v *= scale;
  // Horner: I + m(I + m/2(I + m/3(…))).
  float e[N][N]{};
  for (int i = 0; i < N; ++i) e[i][i] = 1.0f;
  for (int k = 12; k >= 1; --k) {
    float next[N][N]{};
    const float inv_k = 1.0f / static_cast<float>(k);
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        float s = 0.0f;
        for (int l = 0; l < N; ++l) s += m[i][l] * e[l][j];
        next[i][j] = (i == j ? 1.0f : 0.0f) + s * inv_k;
      }
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) e[i][j] = next[i][j];
  }
  for (int s = 0; s < squarings; ++s) {
    float sq[N][N]{};
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        float acc = 0.0f;
        for (int l = 0; l < N; ++l) acc += e[i][l] * e[l][j];
        sq[i][j] = acc;
      }
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) e[i][j] = sq[i][j];
  }
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) out[i][j] = e[i][j];
}

}  // namespace hmp::spidar
