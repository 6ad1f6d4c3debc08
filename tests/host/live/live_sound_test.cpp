// LiveSound: which audio event each live message becomes (the channel filter, the program from the
// instrument or from the input's program changes), and that an event applied at once through the
// AudioPlayer is heard: FluidSynth on the simulated sound card, silent until the key is struck.
#include "host/live/live_sound.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "host/audio/audio_player.hpp"
#include "host/audio/soundfont.hpp"

namespace hmp::live {
namespace {

using Kind = audio::AudioEvent::Kind;
using Control = midi::Control::Kind;

ChannelMessage msg(std::uint8_t status, std::uint8_t d1, std::uint8_t d2 = 0) { return {status, d1, d2}; }

TEST(LiveSound, NotesControlsAndBendsBecomeAudioEvents) {
  LiveSound s(-1, std::nullopt);
  const auto on = s.on_message(msg(0x93, 60, 100));
  ASSERT_TRUE(on);
  EXPECT_EQ(on->kind, Kind::note_on);
  EXPECT_EQ(on->channel, 3);
  EXPECT_EQ(on->key, 60);
  EXPECT_EQ(on->velocity, 100);
  EXPECT_EQ(on->program, 0) << "the piano until a program change";
  for (const ChannelMessage m : {msg(0x83, 60, 64), msg(0x93, 60, 0)}) {
    const auto off = s.on_message(m);
    ASSERT_TRUE(off);
    EXPECT_EQ(off->kind, Kind::note_off);
    EXPECT_EQ(off->key, 60);
  }
  const auto pedal = s.on_message(msg(0xB0, 64, 127));
  ASSERT_TRUE(pedal);
  EXPECT_EQ(pedal->kind, Kind::control);
  EXPECT_EQ(pedal->control, Control::controller);
  EXPECT_EQ(pedal->key, 64);
  EXPECT_EQ(pedal->value, 127);
  const auto bend = s.on_message(msg(0xE1, 0x7F, 0x7F));
  ASSERT_TRUE(bend);
  EXPECT_EQ(bend->control, Control::pitch_bend);
  EXPECT_EQ(bend->value, 16383);
  const auto pressure = s.on_message(msg(0xD2, 90));
  ASSERT_TRUE(pressure);
  EXPECT_EQ(pressure->control, Control::pressure);
  EXPECT_EQ(pressure->value, 90);
  EXPECT_FALSE(s.on_message(msg(0xA0, 60, 10))) << "polyphonic aftertouch";
}

TEST(LiveSound, ProgramChangesUnlessAnInstrumentIsChosen) {
  LiveSound free(-1, std::nullopt);
  EXPECT_FALSE(free.on_message(msg(0xC5, 40)));
  EXPECT_EQ(free.on_message(msg(0x95, 60, 1))->program, 40);
  EXPECT_EQ(free.on_message(msg(0x96, 60, 1))->program, 0) << "a program change is its channel's";
  LiveSound violin(-1, std::uint8_t{40});
  EXPECT_EQ(violin.on_message(msg(0x90, 60, 1))->program, 40);
  violin.on_message(msg(0xC0, 0));
  EXPECT_EQ(violin.on_message(msg(0x90, 60, 1))->program, 40) << "--instrument wins over the input";
}

TEST(LiveSound, OnlyTheChosenChannel) {
  LiveSound s(2, std::nullopt);
  EXPECT_FALSE(s.on_message(msg(0x90, 60, 100)));
  EXPECT_FALSE(s.on_message(msg(0xB1, 64, 127)));
  EXPECT_TRUE(s.on_message(msg(0x92, 60, 100)));
}

// Silence before the key, sound after it: the event reached FluidSynth at once, with no song playing.
TEST(LiveSound, AKeyStruckIsHeardThroughTheAudioPlayer) {
  ASSERT_TRUE(audio::find_soundfont().has_value()) << "no GM SoundFont (fluid-soundfont-gm)";
  audio::AudioOptions ao;
  ao.drivers = {"virtual"};
  ao.synth.reverb = ao.synth.chorus = false;
  ao.virtual_record_frames = static_cast<std::size_t>(20.0 * ao.synth.sample_rate);
  audio::AudioPlayer player(ao);
  ASSERT_NE(player.virtual_card(), nullptr) << player.silence_reason();
  player.set_events({});
  player.start(0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::uint64_t before = player.virtual_card()->frames_played();
  LiveSound s(-1, std::nullopt);
  player.play_now(*s.on_message(msg(0x90, 60, 110)));
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  player.play_now(*s.on_message(msg(0x80, 60, 0)));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  player.stop();
  const std::vector<float> rec = player.virtual_card()->recording();
  ASSERT_GT(rec.size(), before);
  const float silent = *std::max_element(rec.begin(), rec.begin() + static_cast<std::ptrdiff_t>(before));
  const float heard = *std::max_element(rec.begin() + static_cast<std::ptrdiff_t>(before), rec.end());
  EXPECT_EQ(silent, 0.0f) << "nothing was played before the key";
  EXPECT_GT(heard, 0.01f) << "the key was heard";
}

}  // namespace
}  // namespace hmp::live
