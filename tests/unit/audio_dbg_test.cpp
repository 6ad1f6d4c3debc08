#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include "host/audio/offline_render.hpp"
#include "host/audio/soundfont.hpp"
using namespace hmp::audio;
TEST(Dbg, X) {
  std::vector<AudioEvent> ev = {{1000000, AudioEvent::Kind::note_on, 0, 60, 100, 0}, {1300000, AudioEvent::Kind::note_off, 0, 60, 0, 0},
    {1750300, AudioEvent::Kind::note_on, 1, 67, 100, 19}, {2050300, AudioEvent::Kind::note_off, 1, 67, 0, 19}};
  AudioOptions o;
  auto a = render_offline(ev, 0, 2000000, o);
  int shown = 0;
  for (std::size_t i = 0; i < a.left.size() && shown < 5; ++i) if (a.left[i] != 0 || a.right[i] != 0) { std::printf("nonzero at %zu: %g %g\n", i, static_cast<double>(a.left[i]), static_cast<double>(a.right[i])); ++shown; }
}
