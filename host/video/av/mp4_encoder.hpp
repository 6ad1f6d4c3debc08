#pragma once
// host/video/av/: the video module (hmp-video.so): H.264 video and AAC audio in an MP4 file, through
// ffmpeg's libraries (libx264 for the pictures, ffmpeg's own AAC encoder for the sound). The frames come
// as BT.709 limited-range I420 (host/video/yuv_convert.hpp) and the stream is tagged so.
#include <memory>
#include <string>

#include "host/video/video_backend.hpp"

namespace hmp::video::av {

std::unique_ptr<VideoEncoder> open_mp4(const VideoSetup& setup, std::string& error);

}  // namespace hmp::video::av
