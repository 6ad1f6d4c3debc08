#!/usr/bin/env bash
# hmp live: every bad option exits 2 with exactly one line on stderr naming the problem, before any MIDI
# port or device is opened (so these need neither a JACK server nor an ALSA sequencer).
set -u
hmp="$1"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

bad_prefix=(live)
expect_bad "--channel 17: use 1–16" --channel 17
expect_bad "--channel -1: use 1–16" --channel -1
expect_bad "--channel 0: use 1–16 (without --channel: every channel)" --channel 0
expect_bad "the low key is above the high one" --key-range 70:60
expect_bad "expected LOW:HIGH" --key-range 60
expect_bad "each end is a key" --key-range C4:C10
expect_bad "each end is a key" --key-range 0:128
expect_bad "--envelope kazoo: unknown" --envelope kazoo
expect_bad "--mapping wobble: unknown" --mapping wobble
expect_bad "--instrument kazoo: not a GM program" --instrument kazoo
expect_bad "--instrument 0: not a GM program" --instrument 0
expect_bad "--instrument 129: not a GM program" --instrument 129
expect_bad "none.sf2: no such file" --soundfont "$tmp/none.sf2"
expect_bad "--api midi: use alsa or jack" --api midi
expect_bad "--seconds -1: must be ≥ 0" --seconds -1
expect_bad "--vibration-delay-ms -1: a delay from 0 to 1000 ms" --vibration-delay-ms -1
expect_bad "--vibration-delay-ms 1001: a delay from 0 to 1000 ms" --vibration-delay-ms 1001
expect_bad "--vibration-delay-ms nan: a delay from 0 to 1000 ms" --vibration-delay-ms nan
expect_bad "--vibration-delay-ms inf: a delay from 0 to 1000 ms" --vibration-delay-ms inf
expect_bad "no sound to wait for" --sync-sound --no-audio
expect_bad "--sync-sound excludes --vibration-delay-ms" --sync-sound --vibration-delay-ms 20
expect_bad "bad --device 'bogus'" --device bogus --no-audio --no-view --seconds 1
# --seconds bounds the wait for a port too (it waited until killed): whatever the machine's MIDI, exit 0 soon
timeout 20 "$hmp" live --no-audio --no-view --seconds 1 --wait --device sim >"$tmp/out" 2>"$tmp/err" </dev/null
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: live --wait --seconds 1 -> rc=$rc (124: still running after 20 s)"; cat "$tmp/err"; fail=1; }
# A port that never came: the log asked for is still written, its summary saying no note came.
timeout 20 "$hmp" live --no-audio --no-view --seconds 1 --wait --device sim --input "hmp test: no such port" \
  --log "$tmp/none.jsonl" >"$tmp/out" 2>"$tmp/err" </dev/null
[ "$(cat "$tmp/none.jsonl" 2>/dev/null)" = '{"summary":{"bends":0,"dropped":0,"notes_off":0,"notes_on":0,"refused":0,"started":0,"vibration_delay_ms":0.0}}' ] ||
  { echo "FAIL: live --wait with no port: the log is [$(cat "$tmp/none.jsonl" 2>&1)]"; cat "$tmp/err"; fail=1; }
# The log's name is checked first too: an existing file is kept without --force.
echo keep >"$tmp/log.jsonl"
expect_bad "exists" --log "$tmp/log.jsonl"
[ "$(cat "$tmp/log.jsonl")" = keep ] || { echo "FAIL: the log was modified"; fail=1; }

[ $fail -eq 0 ] && echo "live_errors: all passed"
