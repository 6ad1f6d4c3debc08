#include "host/measure/sound_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hmp::measure {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFluidSpanDb = 96.0;   // FluidSynth's decay and release "time" spans 96 dB (960 cB)
constexpr double kSilentPeak = 1e-5;    // −100 dB of the render's full scale: no sound
constexpr double kFloorDb = -70.0;      // below this the fits stop (reverb-free renders stay clean)
constexpr double kReleaseRatio = 0.01;  // Eq. 10's r for measured presets: the release spans 40 dB

double db(double level) { return level > 0 ? 20.0 * std::log10(level) : -400.0; }

// Least-squares line y = a + b·t through points i ∈ [first, last) of `y` (t = i·step).
struct Line {
  double a = 0, b = 0;
  bool ok = false;
};
template <class Y>
Line fit_line(std::size_t first, std::size_t last, double step, Y y) {
  Line l;
  if (last < first + 3) return l;
  double st = 0, sy = 0, stt = 0, sty = 0;
  const auto n = static_cast<double>(last - first);
  for (std::size_t i = first; i < last; ++i) {
    const double t = static_cast<double>(i) * step, v = y(i);
    st += t;
    sy += v;
    stt += t * t;
    sty += t * v;
  }
  const double den = n * stt - st * st;
  if (!(den > 0)) return l;
  l.b = (n * sty - st * sy) / den;
  l.a = (sy - l.b * st) / n;
  l.ok = true;
  return l;
}

std::size_t index_of(const SoundEnvelope& e, double t) {
  const double i = std::floor(t / e.step_s);
  return i <= 0 ? 0 : std::min(e.amplitude.size(), static_cast<std::size_t>(i));
}

}  // namespace

SoundEnvelope envelope_of(const float* left, const float* right, std::size_t frames, int sample_rate,
                          double fundamental_hz, double note_off_s, double step_s) {
  SoundEnvelope e;
  e.step_s = step_s;
  e.note_off_s = note_off_s;
  // Prefix sums of the power, in double: exact enough over minutes of audio.
  std::vector<double> power(frames + 1, 0.0);
  for (std::size_t i = 0; i < frames; ++i) {
    const auto l = static_cast<double>(left[i]), r = static_cast<double>(right[i]);
    power[i + 1] = power[i] + 0.5 * (l * l + r * r);
  }
  const auto window =
      std::max<std::size_t>(8, static_cast<std::size_t>(std::lround(2.0 * sample_rate / fundamental_hz)));
  const auto points = static_cast<std::size_t>(static_cast<double>(frames) / (step_s * sample_rate));
  e.amplitude.resize(points);
  for (std::size_t k = 0; k < points; ++k) {
    const auto centre = static_cast<std::size_t>(std::lround(static_cast<double>(k) * step_s * sample_rate));
    const std::size_t lo = centre > window / 2 ? centre - window / 2 : 0;
    const std::size_t hi = std::min(frames, lo + window);
    const double mean = hi > lo ? (power[hi] - power[lo]) / static_cast<double>(hi - lo) : 0.0;
    e.amplitude[k] = std::sqrt(2.0 * std::max(0.0, mean));
  }
  return e;
}

// A centred moving average over `points` (odd) of the envelope: real instruments beat and vibrate; the
// peak and the sustain are read from this, the line fits from the envelope itself.
std::vector<double> smoothed(const std::vector<double>& a, std::size_t points) {
  std::vector<double> out(a.size());
  double sum = 0;
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::size_t want_lo = i > points / 2 ? i - points / 2 : 0, want_hi = std::min(a.size(), i + points / 2 + 1);
    while (hi < want_hi) sum += a[hi++];
    while (lo < want_lo) sum -= a[lo++];
    out[i] = sum / static_cast<double>(hi - lo);
  }
  return out;
}

Stages fit_stages(const SoundEnvelope& e) {
  Stages s;
  const std::size_t off = index_of(e, e.note_off_s);
  if (off < 10) return s;
  const std::vector<double> smooth =
      smoothed(e.amplitude, 2 * static_cast<std::size_t>(std::lround(0.01 / e.step_s)) + 1);
  s.peak = *std::max_element(e.amplitude.begin(), e.amplitude.begin() + static_cast<std::ptrdiff_t>(off));
  if (!(s.peak > kSilentPeak)) return s;
  s.sounded = true;
  const double step = e.step_s;
  const auto level = [&](std::size_t i) { return e.amplitude[i] / s.peak; };
  const auto level_db = [&](std::size_t i) { return db(level(i)); };
  const auto smooth_db = [&](std::size_t i) { return db(smooth[i] / s.peak); };

  // Attack: linear in amplitude; the line through its 20–85 % part, where the window's smoothing of the
  // corners does not reach, gives its start (level 0) and its end (level 1).
  std::size_t i90 = 0;
  while (i90 < off && level(i90) < 0.9) ++i90;
  std::size_t first = i90;
  while (first > 0 && level(first - 1) >= 0.2) --first;
  std::size_t last = first;
  while (last < i90 && level(last) <= 0.85) ++last;
  const Line attack = fit_line(first, last, step, level);
  double attack_end = static_cast<double>(i90) * step;
  if (attack.ok && attack.b > 0) {
    s.delay_s = std::max(0.0, -attack.a / attack.b);
    attack_end = (1.0 - attack.a) / attack.b;
  } else {  // too fast to see a slope: the start is where it first rises above 10 %
    std::size_t i10 = 0;
    while (i10 < i90 && level(i10) < 0.1) ++i10;
    s.delay_s = static_cast<double>(i10) * step;
  }
  s.attack_s = std::max(0.0, attack_end - s.delay_s);

  // Sustain: level (within 3 dB/s) over the last 0.8 s before the note-off, and audible; otherwise the
  // sound is still falling when released and is taken to die away (sustain 0).
  s.level_at_off = smooth[off - 1] / s.peak;
  const std::size_t from = off - std::min(off - 1, static_cast<std::size_t>(std::lround(0.8 / step)));
  const Line tail = fit_line(from, off, step, smooth_db);
  const bool sustains = tail.ok && std::abs(tail.b) < 3.0 && smooth_db(off - 1) > kFloorDb + 10;
  double sustain_db = -400;
  if (sustains) {
    double sum = 0;
    for (std::size_t i = from; i < off; ++i) sum += smooth[i];
    s.sustain = std::min(1.0, sum / static_cast<double>(off - from) / s.peak);
    sustain_db = db(s.sustain);
  } else {
    s.sustain = 0;
  }

  // Decay: linear in dB from the end of the hold down to the sustain level; fitted between 2 dB below
  // the peak and 2 dB above the sustain (or the floor), clear of the window's rounding of both corners.
  const double stop_db = sustains ? sustain_db + 2.0 : kFloorDb;
  std::size_t d0 = static_cast<std::size_t>(std::max(0.0, std::ceil(attack_end / step)));
  while (d0 < off && level_db(d0) > -2.0) ++d0;
  std::size_t d1 = d0;
  while (d1 < off && level_db(d1) > stop_db) ++d1;
  const Line decay = (sustains && sustain_db > -2.5) ? Line{} : fit_line(d0, d1, step, level_db);
  if (decay.ok && decay.b < 0) {
    s.decay_s = kFluidSpanDb / -decay.b;
    const double hold_end = -decay.a / decay.b;  // where the line leaves 0 dB
    s.hold_s = std::max(0.0, hold_end - attack_end);
  } else {
    s.decay_s = kNaN;
    s.hold_s = 0;
  }
  s.release_s = release_of(e);
  return s;
}

double release_of(const SoundEnvelope& e) {
  const std::size_t off = index_of(e, e.note_off_s);
  if (off < 1 || off >= e.amplitude.size()) return kNaN;
  double peak = 0;
  for (std::size_t i = 0; i < off; ++i) peak = std::max(peak, e.amplitude[i]);
  if (!(peak > kSilentPeak)) return kNaN;
  const auto level_db = [&](std::size_t i) { return db(e.amplitude[i] / peak); };
  const double at_off = level_db(off - 1);
  if (at_off < kFloorDb + 20) return kNaN;  // too quiet at the note-off to see 20 dB of release
  // Linear in dB from the note-off on: fitted from 2 dB below the level at the note-off to 40 dB below
  // it (or the floor), past the window's rounding of the corner.
  std::size_t r0 = off;
  while (r0 < e.amplitude.size() && level_db(r0) > at_off - 2.0) ++r0;
  std::size_t r1 = r0;
  const double stop = std::max(at_off - 40.0, kFloorDb);
  while (r1 < e.amplitude.size() && level_db(r1) > stop) ++r1;
  const Line release = fit_line(r0, r1, e.step_s, level_db);
  return release.ok && release.b < 0 ? kFluidSpanDb / -release.b : kNaN;
}

double time_to_fall_to(const SoundEnvelope& e, const Stages& s, double level) {
  if (!s.sounded) return kNaN;
  for (std::size_t i = index_of(e, s.delay_s + s.attack_s); i < e.amplitude.size(); ++i) {
    if (e.amplitude[i] / s.peak <= level) return static_cast<double>(i) * e.step_s;
  }
  return kNaN;
}

namespace {

// Calls visit(point) for each point of preset_curve() without storing them (the fit evaluates it ~1,000
// times per program).
template <class Visit>
void visit_curve(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset, double duration_s,
                 Visit visit) {
  constexpr double kTickHz = 1000.0;  // the envelope is compared every millisecond, as the device plays it
  envelope::Envelope env;
  const auto ticks = static_cast<std::uint32_t>(std::max(1.0, std::round(duration_s * kTickHz)));
  env.start(preset, 1.0f, ticks, static_cast<float>(kTickHz), 0.0f);
  for (std::uint32_t k = 0; k < ticks; ++k) {
    const std::size_t i = index_of(e, s.delay_s + k / kTickHz);
    if (i >= e.amplitude.size()) break;
    visit(CurvePoint{i, static_cast<double>(env.at(k))});
  }
}

}  // namespace

double note_duration(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset) {
  return std::max(0.001, e.note_off_s - s.delay_s) + static_cast<double>(preset.release_ms) * 1e-3;
}

std::vector<CurvePoint> preset_curve(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset,
                                     double duration_s) {
  std::vector<CurvePoint> out;
  visit_curve(e, s, preset, duration_s, [&](const CurvePoint& p) { out.push_back(p); });
  return out;
}

double rms_error(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset, double duration_s) {
  double sum = 0;
  std::size_t n = 0;
  visit_curve(e, s, preset, duration_s, [&](const CurvePoint& p) {
    const double d = e.amplitude[p.index] / s.peak - p.value;
    sum += d * d;
    ++n;
  });
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

namespace {

// The value of one parameter in [lo, hi] with the least error, given the others: a 32-point grid (log-
// spaced from lo > 0, or linear from 0), then golden section between the best point's neighbours. The
// error function need not be unimodal over the whole range, only near its best grid point.
template <class Error>
double least_error(double current, double lo, double hi, bool log_spaced, Error error, double& best) {
  constexpr int kGrid = 32;
  const auto at = [&](int g) {
    const double u = g / static_cast<double>(kGrid);
    return log_spaced ? lo * std::pow(hi / lo, u) : lo + (hi - lo) * u;
  };
  double best_x = current;
  int best_g = -1;
  for (int g = 0; g <= kGrid; ++g) {
    if (const double err = error(at(g)); err < best) {
      best = err;
      best_x = at(g);
      best_g = g;
    }
  }
  if (best_g < 0) return current;
  double x0 = at(std::max(0, best_g - 1)), x3 = at(std::min(kGrid, best_g + 1));
  constexpr double kGolden = 0.6180339887498949;
  for (int it = 0; it < 24; ++it) {
    const double x1 = x3 - kGolden * (x3 - x0), x2 = x0 + kGolden * (x3 - x0);
    if (error(x1) < error(x2))
      x3 = x2;
    else
      x0 = x1;
  }
  if (const double err = error(0.5 * (x0 + x3)); err < best) {
    best = err;
    best_x = 0.5 * (x0 + x3);
  }
  return best_x;
}

}  // namespace

envelope::Adsr fit_adsr(const SoundEnvelope& e, const Stages& s, double* rms) {
  envelope::Adsr a;
  a.shape = envelope::Shape::adsr;
  a.attack_ms = static_cast<float>(s.attack_s * 1e3);
  a.sustain = static_cast<float>(std::clamp(s.sustain, 0.0, 1.0));
  // Eq. 10 falls by log(r) over R, as FluidSynth's release falls 96 dB per release_s: the same curve
  // with r = 1 % has R = the time to fall 40 dB.
  const double release_s = std::isnan(s.release_s) ? 0.0 : s.release_s * (-db(kReleaseRatio)) / kFluidSpanDb;
  a.release_ms = static_cast<float>(release_s * 1e3);
  a.final_ratio = static_cast<float>(release_s > 0 ? kReleaseRatio : 1.0);
  const double duration = note_duration(e, s, a);
  const double held_ms = std::max(1.0, (e.note_off_s - s.delay_s) * 1e3);
  double best = rms_error(e, s, a, duration);
  // Starting from the stages, A, Dc and S are adjusted in turn for the least RMS error: Eq. 9's decay is
  // linear in amplitude where FluidSynth's is linear in dB, and real instruments beat and swell where
  // the stages assume straight lines.
  const auto with = [&](float envelope::Adsr::*field, double v) {
    envelope::Adsr t = a;
    t.*field = static_cast<float>(v);
    return rms_error(e, s, t, duration);
  };
  for (int sweep = 0; sweep < 2; ++sweep) {
    a.decay_ms = static_cast<float>(least_error(
        static_cast<double>(a.decay_ms), 0.5, held_ms, true,
        [&](double v) { return with(&envelope::Adsr::decay_ms, v); }, best));
    a.attack_ms = static_cast<float>(least_error(
        static_cast<double>(a.attack_ms), 0.5, held_ms, true,
        [&](double v) { return with(&envelope::Adsr::attack_ms, v); }, best));
    a.sustain = static_cast<float>(least_error(
        static_cast<double>(a.sustain), 0.0, 1.0, false, [&](double v) { return with(&envelope::Adsr::sustain, v); },
        best));
  }
  if (rms) *rms = best;
  return a;
}

}  // namespace hmp::measure
