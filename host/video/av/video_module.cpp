// The video module's entry (hmp-video.so): the VideoBackend over ffmpeg's libraries.
#include "host/modules/module_loader.hpp"
#include "host/video/av/mp4_encoder.hpp"

namespace hmp::video::av {
namespace {

class AvBackend final : public VideoBackend {
 public:
  std::unique_ptr<VideoEncoder> open(const VideoSetup& setup, std::string& error) const override {
    return open_mp4(setup, error);
  }
};

}  // namespace
}  // namespace hmp::video::av

HMP_DEFINE_MODULE(hmp::video::VideoBackend, hmp::video::av::AvBackend)
