#pragma once
// Writes a haptic signal in the format the output path names: .csv (t_s,value), .wav (float at the tick
// rate, or 44.1 kHz with `audible`), .png (plot with the notes above the waveform). "-" is CSV on stdout.
#include <span>
#include <string>

#include "host/output/signal_plot.hpp"

namespace hmp::exporting {

struct SignalExport {
  std::string path = "-";
  bool audible = false;
  bool force = false;
};

// Whether `path` names one of the signal's formats: .csv, .wav, .png, or "-".
bool is_signal_export(const std::string& path);
// Throws BadInput for an unknown extension or --audible without .wav (call before long work).
void check_export(const SignalExport& e);
void export_signal(const SignalExport& e, std::span<const float> samples, std::span<const output::PlotNote> notes,
                   const output::PlotSpec& spec);

}  // namespace hmp::exporting
