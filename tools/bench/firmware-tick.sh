#!/usr/bin/env bash
# firmware-tick (design §8 budget: 16 voices ≤ 1,500 instructions per tick; the full tick with the SPIDAR drive
# ≤ 12,000): instructions per device tick of the qemu-an386 firmware (Cortex-M4F build) with 0, 1, 4, 8 and
# 16 sounding voices, at 1 kHz and 10 kHz; and with the drive ("drive":true rows: the board given simulated
# motors whose encoders report a moving grip) with 0 and 16 voices.
#
# Method (boards/qemu-an386/instruction_counter.hpp, docs/performance.md "Firmware tick"): the bench image
# hmp_fw_qemu_an386_bench runs the real board tick (An386Board::on_tick: core tick, output, report
# hand-off) under `qemu-system-arm -icount shift=0`, where every instruction advances virtual time by
# exactly 1 ns. It reads virtual time from a 25 MHz hardware timer around each tick, synchronised to the
# timer's count edges, which resolves single instructions; a run of 1000 nops must count 1000 (checked).
# Prints the mean over 2 s of ticks with every voice sounding (metric instructions_per_tick), the worst of
# those ticks (…_max), the two heaviest ticks a host can cause (instructions_worst_tick: taking four full
# note reports; starting 16 notes at once) and the cost of the pieces (instructions_detail), among them
# the heaviest 16-voice tick of each kind (part max_by_kind_16_voices[_drive]_KIND: what else the tick did —
# plain, note_start, report, status (any report sent), prepare_request, or a `+` of them). The core's
# background work (Core::poll: encoding and sending reports, preparing voices) runs between the ticks,
# as the board's main loop does, and is not counted: it is not part of the tick.
#
# Run by scripts/bench with the host build directory as $1 (unused: the image comes from the cross tree,
# build/qemu-an386, or $HMP_QEMU_BUILD_DIR, configured and built here).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/an386-counted.sh"

for hz in 1000 10000; do
  out=$(an386_counted firmware-tick hmp_fw_qemu_an386_bench 300 "hz=$hz")
  awk -v hz="$hz" '
    function field(name,   i, kv) {
      for (i = 2; i <= NF; ++i) { split($i, kv, "="); if (kv[1] == name) return kv[2] }
      return ""
    }
    function emit(metric, value, params, drive) {
      printf "{\"bench\":\"firmware-tick\",\"metric\":\"%s\",\"value\":%s,\"unit\":\"instructions\",\"params\":{%s\"drive\":%s,\"board\":\"qemu-an386\",\"tick_hz\":%d}}\n", metric, value, params, (drive == "" ? "false" : drive), hz
    }
    $1 == "result" {
      v = "\"voices\":" field("voices") ","
      # drive: false; true (the whole drive in the tick, design §8 ≤ 12,000); "split" (pose and QP planned at
      # 1 kHz outside the tick: the tick ≤ 2,500, and per ms ≤ 60,000 with the plan)
      d = field("drive") == "1" ? "true" : field("drive") == "split" ? "\"split\"" : "false"
      emit("instructions_per_tick", field("mean"), v, d)
      emit("instructions_per_tick_max", field("max"), v, d)
      if (d == "\"split\"") {
        emit("instructions_per_plan", field("plan_mean"), v, d)
        emit("instructions_per_plan_max", field("plan_max"), v, d)
        # The worst millisecond: every tick of it at its max, and one plan at its max.
        emit("instructions_per_ms_worst", field("max") * hz / 1000 + field("plan_max"), v, d)
      }
    }
    $1 == "detail:" {
      for (i = 2; i <= NF; ++i) {
        split($i, kv, "=")
        if (kv[2] == "") { what = $i; continue }  # "envelope_at" names the group of the phases after it
        if (what == "worst") { emit("instructions_worst_tick", kv[2], "\"case\":\"" kv[1] "\","); continue }
        part = (what == "" ? kv[1] : what "_" kv[1])
        emit("instructions_detail", kv[2], "\"part\":\"" part "\",")
      }
      what = ""
    }' <<<"$out"
done
