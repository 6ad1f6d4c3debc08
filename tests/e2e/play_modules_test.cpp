// A player that makes no sound maps no sound library (host/modules/, docs/host.md): a passage played on
// the simulated device without audio, then this process's own memory map (/proc/self/maps) searched for
// the audio module and the libraries behind it. The same search after opening the virtual sound card
// finds them, so the search can fail.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "host/audio/audio_player.hpp"
#include "host/modules/module_loader.hpp"
#include "host/transport/sim_transport.hpp"
#include "play_harness.hpp"

namespace {

using namespace std::chrono_literals;

// Which of `names` appear in the paths of this process's mapped files, in the order given.
std::string mapped(std::initializer_list<const char*> names) {
  std::ifstream maps("/proc/self/maps");
  std::string all, line;
  while (std::getline(maps, line)) all += line + "\n";
  std::string found;
  for (const char* name : names) {
    if (all.find(name) != std::string::npos) found += std::string(name) + " ";
  }
  return found;
}

constexpr auto kSoundAndPictures = {"hmp-audio.so",  "hmp-plot.so", "hmp-usb.so", "libfluidsynth",
                                    "libSDL2",       "libasound",   "libpulse",   "libsndfile",
                                    "libsamplerate", "libcairo",    "libhidapi",  "libusb-1.0"};

TEST(PlayModules, PlayingWithoutSoundMapsNoSoundLibrary) {
  ASSERT_EQ(mapped({"libstdc++"}), "libstdc++ ") << "the search of /proc/self/maps does not work";
  {
    hmp::transport::SimTransport sim;
    hmp::test::Session s(sim, hmp::test::passage(1, 130, 131.5));
    s.start();
    s.join();
    ASSERT_EQ(s.outcome(), hmp::player::Outcome::finished) << s.error();
    EXPECT_GT(s.player().counters().notes_played, 3u);
  }
  EXPECT_EQ(mapped(kSoundAndPictures), "");
  EXPECT_EQ(hmp::modules::loaded_summary(), "none");

  // With the virtual card the audio module comes in, and FluidSynth with it (not the plots or USB).
  hmp::audio::AudioOptions options;
  options.drivers = {"virtual"};
  hmp::audio::AudioPlayer audio(options, [](const std::string& w) { ADD_FAILURE() << w; });
  ASSERT_TRUE(audio.audible()) << audio.silence_reason();
  EXPECT_EQ(mapped(kSoundAndPictures),
            "hmp-audio.so libfluidsynth libSDL2 libasound libpulse libsndfile libsamplerate ");
  EXPECT_EQ(hmp::modules::loaded_summary(), "audio");
}

}  // namespace
