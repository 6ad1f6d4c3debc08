#pragma once
// The video module's interface (module "video", host/video/av/): an MP4 writer over ffmpeg's libraries
// (libavformat, libavcodec with libx264). hmp hands it finished frames (I420 planes) and finished audio
// (float samples) in step; it encodes and muxes. Errors come back as values in one line.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hmp::video {

struct AudioStreamSetup {
  int channels = 2;      // 1 or 2
  std::string title;     // the stream's name in players ("song", "haptic signal")
  int bitrate = 192000;  // AAC, bits per second
};

struct VideoSetup {
  std::string path;                // written as given (the caller picks a temporary name)
  int width = 1280, height = 720;  // even numbers (4:2:0 chroma)
  int fps = 60;                    // frames per second; the audio holds sample_rate / fps samples a frame
  int sample_rate = 44100;
  std::vector<AudioStreamSetup> audio;  // in this order after the video stream
  std::string preset = "ultrafast";     // libx264's speed/size trade-off
  int crf = 20;                         // libx264's constant quality (lower: better, bigger)
  std::string title, comment;           // the file's metadata
};

class VideoEncoder {
 public:
  virtual ~VideoEncoder() = default;
  // One frame in I420 (BT.709 limited range): planes of width × height and width/2 × height/2 bytes, rows
  // from the top, no padding (host/video/yuv_convert.hpp converts to it).
  virtual bool add_frame_i420(const std::uint8_t* y, const std::uint8_t* u, const std::uint8_t* v) = 0;
  // Samples of audio stream `stream`: `channels` planes of `count` samples each.
  virtual bool add_audio(int stream, const float* const* planes, std::size_t count) = 0;
  // Flushes the encoders and writes the index. The file is complete only after this returns true.
  virtual bool finish() = 0;
  virtual std::string error() const = 0;
  virtual std::string summary() const = 0;  // "h264 (libx264 veryfast, crf 20) 1280x720 60 fps + aac 44100 Hz stereo"
};

class VideoBackend {
 public:
  static constexpr const char* kModule = "video";
  static constexpr int kAbi = 1;
  virtual std::unique_ptr<VideoEncoder> open(const VideoSetup& setup, std::string& error) const = 0;

 protected:
  ~VideoBackend() = default;
};

}  // namespace hmp::video
