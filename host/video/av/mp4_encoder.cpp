#include "host/video/av/mp4_encoder.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/opt.h>
}

#include <algorithm>
#include <vector>

namespace hmp::video::av {
namespace {

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

struct CodecContextFree {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameFree {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketFree {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextFree>;
using FramePtr = std::unique_ptr<AVFrame, FrameFree>;
using PacketPtr = std::unique_ptr<AVPacket, PacketFree>;

// One encoder and its stream in the file.
struct Track {
  CodecContextPtr codec;
  AVStream* stream = nullptr;
  FramePtr frame;
  std::int64_t next_pts = 0;                // in the codec's time base
  std::vector<std::vector<float>> pending;  // audio: samples not yet a whole codec frame, per channel
};

class Mp4Encoder final : public VideoEncoder {
 public:
  explicit Mp4Encoder(const VideoSetup& setup) : setup_(setup) {}
  ~Mp4Encoder() override;

  bool start(std::string& error);
  bool add_frame_i420(const std::uint8_t* y, const std::uint8_t* u, const std::uint8_t* v) override;
  bool add_audio(int stream, const float* const* planes, std::size_t count) override;
  bool finish() override;
  std::string error() const override { return error_; }
  std::string summary() const override { return summary_; }

 private:
  bool fail(const std::string& what, int code) {
    error_ = what + ": " + av_message(code);
    return false;
  }
  bool open_video(std::string& error);
  bool open_audio(const AudioStreamSetup& a, std::string& error);
  bool encode(Track& t, AVFrame* frame);  // frame null: flush
  bool encode_audio_frames(Track& t, bool last);

  VideoSetup setup_;
  AVFormatContext* format_ = nullptr;
  bool io_open_ = false, finished_ = false;
  Track video_;
  std::vector<Track> audio_;
  PacketPtr packet_{av_packet_alloc()};
  std::string error_, summary_;
};

Mp4Encoder::~Mp4Encoder() {
  if (format_ != nullptr) {
    if (io_open_) avio_closep(&format_->pb);
    avformat_free_context(format_);
  }
}

bool Mp4Encoder::open_video(std::string& error) {
  // H.264 plays everywhere a demo video goes; Debian's ffmpeg has it through libx264.
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  if (codec == nullptr) {
    error = "this ffmpeg has no H.264 encoder (libx264); Debian's libavcodec59 has it";
    return false;
  }
  video_.codec.reset(avcodec_alloc_context3(codec));
  AVCodecContext* c = video_.codec.get();
  c->width = setup_.width;
  c->height = setup_.height;
  c->time_base = AVRational{1, setup_.fps};
  c->framerate = AVRational{setup_.fps, 1};
  c->pix_fmt = AV_PIX_FMT_YUV420P;
  c->gop_size = setup_.fps * 2;  // a key frame every 2 s: seeking in players stays quick
  c->colorspace = AVCOL_SPC_BT709;
  c->color_primaries = AVCOL_PRI_BT709;
  c->color_trc = AVCOL_TRC_BT709;
  c->color_range = AVCOL_RANGE_MPEG;
  if (format_->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  AVDictionary* options = nullptr;
  av_dict_set(&options, "preset", setup_.preset.c_str(), 0);
  av_dict_set(&options, "crf", std::to_string(setup_.crf).c_str(), 0);
  av_dict_set(&options, "tune", "animation", 0);  // flat colours and sharp edges: the piano roll
  const int rc = avcodec_open2(c, codec, &options);
  av_dict_free(&options);
  if (rc < 0) {
    error =
        std::string("cannot open the ") + codec->name + " encoder (preset " + setup_.preset + "): " + av_message(rc);
    return false;
  }
  video_.stream = avformat_new_stream(format_, nullptr);
  avcodec_parameters_from_context(video_.stream->codecpar, c);
  video_.stream->time_base = c->time_base;
  video_.stream->avg_frame_rate = c->framerate;
  video_.frame.reset(av_frame_alloc());
  video_.frame->format = c->pix_fmt;
  video_.frame->width = c->width;
  video_.frame->height = c->height;
  if (const int r = av_frame_get_buffer(video_.frame.get(), 0); r < 0) {
    error = "cannot allocate a video frame: " + av_message(r);
    return false;
  }
  summary_ = "h264 (libx264 " + setup_.preset + ", crf " + std::to_string(setup_.crf) + ")";
  summary_ +=
      " " + std::to_string(c->width) + "x" + std::to_string(c->height) + " " + std::to_string(setup_.fps) + " fps";
  return true;
}

bool Mp4Encoder::open_audio(const AudioStreamSetup& a, std::string& error) {
  const AVCodec* codec = avcodec_find_encoder(AV_CODEC_ID_AAC);
  if (codec == nullptr) {
    error = "ffmpeg has no AAC encoder";
    return false;
  }
  Track t;
  t.codec.reset(avcodec_alloc_context3(codec));
  AVCodecContext* c = t.codec.get();
  c->sample_fmt = AV_SAMPLE_FMT_FLTP;
  c->sample_rate = setup_.sample_rate;
  c->bit_rate = a.bitrate;
  av_channel_layout_default(&c->ch_layout, a.channels);
  c->time_base = AVRational{1, setup_.sample_rate};
  if (format_->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (const int rc = avcodec_open2(c, codec, nullptr); rc < 0) {
    error = "cannot open the AAC encoder: " + av_message(rc);
    return false;
  }
  t.stream = avformat_new_stream(format_, nullptr);
  avcodec_parameters_from_context(t.stream->codecpar, c);
  t.stream->time_base = c->time_base;
  if (!a.title.empty()) av_dict_set(&t.stream->metadata, "title", a.title.c_str(), 0);
  if (!a.title.empty()) av_dict_set(&t.stream->metadata, "handler_name", a.title.c_str(), 0);
  t.stream->disposition = audio_.empty() ? AV_DISPOSITION_DEFAULT : 0;  // players pick the song first
  t.frame.reset(av_frame_alloc());
  t.frame->format = c->sample_fmt;
  t.frame->nb_samples = c->frame_size;
  t.frame->sample_rate = c->sample_rate;
  av_channel_layout_copy(&t.frame->ch_layout, &c->ch_layout);
  if (const int r = av_frame_get_buffer(t.frame.get(), 0); r < 0) {
    error = "cannot allocate an audio frame: " + av_message(r);
    return false;
  }
  t.pending.resize(static_cast<std::size_t>(a.channels));
  audio_.push_back(std::move(t));
  summary_ +=
      std::string(" + aac ") + std::to_string(setup_.sample_rate) + " Hz " + (a.channels == 1 ? "mono" : "stereo");
  if (!a.title.empty()) summary_ += " (" + a.title + ")";
  return true;
}

bool Mp4Encoder::start(std::string& error) {
  if (setup_.width % 2 != 0 || setup_.height % 2 != 0 || setup_.width < 16 || setup_.height < 16) {
    error = "frame size must be even and at least 16x16";
    return false;
  }
  if (setup_.fps < 1 || setup_.sample_rate % setup_.fps != 0) {
    error = "the sample rate must hold a whole number of samples per frame";
    return false;
  }
  if (const int rc = avformat_alloc_output_context2(&format_, nullptr, "mp4", setup_.path.c_str()); rc < 0) {
    error = "cannot set up an MP4 file: " + av_message(rc);
    return false;
  }
  if (!open_video(error)) return false;
  for (const AudioStreamSetup& a : setup_.audio) {
    if (a.channels < 1 || a.channels > 2) {
      error = "audio streams are mono or stereo";
      return false;
    }
    if (!open_audio(a, error)) return false;
  }
  if (!setup_.title.empty()) av_dict_set(&format_->metadata, "title", setup_.title.c_str(), 0);
  if (!setup_.comment.empty()) av_dict_set(&format_->metadata, "comment", setup_.comment.c_str(), 0);
  if (const int rc = avio_open(&format_->pb, setup_.path.c_str(), AVIO_FLAG_WRITE); rc < 0) {
    error = "cannot write " + setup_.path + ": " + av_message(rc);
    return false;
  }
  io_open_ = true;
  AVDictionary* options = nullptr;
  av_dict_set(&options, "movflags", "+faststart", 0);  // the index first: a web page plays it while loading
  const int rc = avformat_write_header(format_, &options);
  av_dict_free(&options);
  if (rc < 0) {
    error = "cannot write the MP4 header: " + av_message(rc);
    return false;
  }
  return true;
}

bool Mp4Encoder::encode(Track& t, AVFrame* frame) {
  if (const int rc = avcodec_send_frame(t.codec.get(), frame); rc < 0) return fail("encoding", rc);
  for (;;) {
    const int rc = avcodec_receive_packet(t.codec.get(), packet_.get());
    if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return true;
    if (rc < 0) return fail("encoding", rc);
    av_packet_rescale_ts(packet_.get(), t.codec->time_base, t.stream->time_base);
    packet_->stream_index = t.stream->index;
    if (const int w = av_interleaved_write_frame(format_, packet_.get()); w < 0)
      return fail("writing " + setup_.path, w);
  }
}

bool Mp4Encoder::add_frame_i420(const std::uint8_t* y, const std::uint8_t* u, const std::uint8_t* v) {
  if (finished_) return false;
  AVFrame* f = video_.frame.get();
  if (const int rc = av_frame_make_writable(f); rc < 0) return fail("video frame", rc);
  const std::uint8_t* planes[3] = {y, u, v};
  const int widths[3] = {setup_.width, setup_.width / 2, setup_.width / 2};
  const int heights[3] = {setup_.height, setup_.height / 2, setup_.height / 2};
  for (int p = 0; p < 3; ++p) {  // the frame's rows may be padded; ours are not
    for (int row = 0; row < heights[p]; ++row) {
      std::copy_n(planes[p] + static_cast<std::ptrdiff_t>(row) * widths[p], widths[p],
                  f->data[p] + static_cast<std::ptrdiff_t>(row) * f->linesize[p]);
    }
  }
  f->pts = video_.next_pts++;
  return encode(video_, f);
}

bool Mp4Encoder::encode_audio_frames(Track& t, bool last) {
  const auto size = static_cast<std::size_t>(t.codec->frame_size);
  while (!t.pending[0].empty() && (t.pending[0].size() >= size || last)) {
    AVFrame* f = t.frame.get();
    if (const int rc = av_frame_make_writable(f); rc < 0) return fail("audio frame", rc);
    const std::size_t n = std::min(size, t.pending[0].size());
    f->nb_samples = static_cast<int>(n);  // the last frame may be short: the file's audio ends where the video does
    for (std::size_t ch = 0; ch < t.pending.size(); ++ch) {
      std::copy_n(t.pending[ch].begin(), n, reinterpret_cast<float*>(f->data[ch]));
      t.pending[ch].erase(t.pending[ch].begin(), t.pending[ch].begin() + static_cast<std::ptrdiff_t>(n));
    }
    f->pts = t.next_pts;
    t.next_pts += static_cast<std::int64_t>(n);
    if (!encode(t, f)) return false;
  }
  return true;
}

bool Mp4Encoder::add_audio(int stream, const float* const* planes, std::size_t count) {
  if (finished_ || stream < 0 || static_cast<std::size_t>(stream) >= audio_.size()) return false;
  Track& t = audio_[static_cast<std::size_t>(stream)];
  for (std::size_t ch = 0; ch < t.pending.size(); ++ch)
    t.pending[ch].insert(t.pending[ch].end(), planes[ch], planes[ch] + count);
  return encode_audio_frames(t, false);
}

bool Mp4Encoder::finish() {
  if (finished_) return error_.empty();
  finished_ = true;
  for (Track& t : audio_) {
    if (!encode_audio_frames(t, true) || !encode(t, nullptr)) return false;
  }
  if (!encode(video_, nullptr)) return false;
  if (const int rc = av_write_trailer(format_); rc < 0) return fail("finishing " + setup_.path, rc);
  if (const int rc = avio_closep(&format_->pb); rc < 0) return fail("closing " + setup_.path, rc);
  io_open_ = false;
  return true;
}

}  // namespace

std::unique_ptr<VideoEncoder> open_mp4(const VideoSetup& setup, std::string& error) {
  av_log_set_level(AV_LOG_ERROR);  // libx264's banner and statistics stay off the terminal
  auto encoder = std::make_unique<Mp4Encoder>(setup);
  if (!encoder->start(error)) return nullptr;
  return encoder;
}

}  // namespace hmp::video::av
