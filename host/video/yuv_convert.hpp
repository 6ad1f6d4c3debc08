#pragma once
// RGB frames to the planes H.264 encoders take (I420: Y at full size, U and V at half size in both
// directions), BT.709 limited range, in fixed point. Ours rather than libswscale's because this is the
// video export's hottest loop: it takes about a third of swscale's time here, and it reads OpenGL's
// bottom-up rows directly, so the frame is never copied before it is converted (docs/performance.md).
#include <cstddef>
#include <cstdint>

namespace hmp::video {

struct I420Planes {
  std::uint8_t* y = nullptr;  // width × height
  std::uint8_t* u = nullptr;  // width/2 × height/2
  std::uint8_t* v = nullptr;
};

// The plane sizes in one buffer of i420_bytes(w, h): Y, then U, then V, rows without padding.
inline std::size_t i420_bytes(int width, int height) {
  return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3 / 2;
}
I420Planes i420_planes(std::uint8_t* buffer, int width, int height);

// `rgba`: width × height pixels, 4 bytes each, rows from the bottom up (as glReadPixels returns them);
// width and height even. Each chroma sample is the mean of its 2×2 pixels (centred siting).
//   Y = 16 + 219·(0.2126 R + 0.7152 G + 0.0722 B)/255,
//   U = 128 + 224·(B − Y')/(1.8556·255), V = 128 + 224·(R − Y')/(1.5748·255)   (ITU-R BT.709-6 §3.2, §3.4)
// rounded to nearest: each value within 0.512 of the exact formula (the matrix is Q15 fixed point).
void rgba_bottom_up_to_i420(const std::uint8_t* rgba, int width, int height, const I420Planes& out);

}  // namespace hmp::video
