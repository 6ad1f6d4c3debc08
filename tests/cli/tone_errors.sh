#!/usr/bin/env bash
# hmp tone: every bad input exits 2 with exactly one line on stderr naming the problem; good input exits 0.
set -u
hmp="$1"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

bad_prefix=(tone)

ok=(--amp 0.5 --ms 100 --instrument organ)
expect_bad "freq" --freq nan "${ok[@]}"
expect_bad "freq" --freq -5 "${ok[@]}"
expect_bad "freq" --freq 0 "${ok[@]}"
expect_bad "alias" --freq 450 "${ok[@]}"
expect_bad "freq" --freq abc "${ok[@]}"
expect_bad "amp" --freq 100 --amp 1.5 --ms 100 --instrument organ
expect_bad "amp" --freq 100 --amp 0 --ms 100 --instrument organ
expect_bad "amp" --freq 100 --amp nan --ms 100 --instrument organ
expect_bad "ms" --freq 100 --amp 0.5 --ms -1 --instrument organ
expect_bad "ms" --freq 100 --amp 0.5 --ms inf --instrument organ
# A day at 50 kHz is 4.32·10⁹ samples: more than one WAV holds (and than a note's 32-bit tick count), refused
# before any work instead of wrapping to 500 s
expect_bad "--ms 86400000 at --tick-hz 50000: 4320000000 samples, more than the 1073740799" --freq 100 --amp 0.5 --ms 86400000 --tick-hz 50000 --instrument organ --out "$tmp/day.wav"
[ -e "$tmp/day.wav" ] && { echo "FAIL: a WAV written for a day at 50 kHz"; fail=1; }
expect_bad "kazoo" --freq 100 --amp 0.5 --ms 100 --instrument kazoo
expect_bad "instrument" --freq 100 --amp 0.5 --ms 100
expect_bad "excludes" --freq 100 --amp 0.5 --ms 100 --instrument organ --adsr attack=1
expect_bad "unknown key" --freq 100 --amp 0.5 --ms 100 --adsr attack=1,wobble=3
expect_bad "sustain" --freq 100 --amp 0.5 --ms 100 --adsr sustain=150
expect_bad "attack" --freq 100 --amp 0.5 --ms 100 --adsr attack=-3
expect_bad "number" --freq 100 --amp 0.5 --ms 100 --adsr attack=nan
expect_bad "key=value" --freq 100 --amp 0.5 --ms 100 --adsr attack
expect_bad "does not exist" --freq 100 "${ok[@]}" --out "$tmp/no/such/dir/x.csv"

# A good run writes a CSV with the header and N = round(ms) rows at 1 kHz.
"$hmp" tone --freq 100 "${ok[@]}" --out "$tmp/a.csv" 2>"$tmp/err" || { echo "FAIL: good tone run"; cat "$tmp/err"; fail=1; }
[ "$(head -1 "$tmp/a.csv")" = "t_s,value" ] || { echo "FAIL: header"; fail=1; }
[ "$(($(wc -l <"$tmp/a.csv") - 1))" = 100 ] || { echo "FAIL: row count $(wc -l <"$tmp/a.csv")"; fail=1; }
# The existing file is not overwritten without --force (no terminal here to ask).
before=$(md5sum <"$tmp/a.csv")
expect_bad "exists" --freq 200 "${ok[@]}" --out "$tmp/a.csv"
[ "$(md5sum <"$tmp/a.csv")" = "$before" ] || { echo "FAIL: file was modified"; fail=1; }
"$hmp" tone --freq 200 "${ok[@]}" --out "$tmp/a.csv" --force || { echo "FAIL: --force"; fail=1; }

[ $fail -eq 0 ] && echo "tone_errors: all passed"
exit $fail
