#!/usr/bin/env bash
# hmp sim's plant options: every bad value of --string-stiffness, --max-step, --integrator and [plant]
# (≤ 0, NaN, infinite, beyond 1e9, a max step below 1e-7 s, unknown) exits 2 with one line on stderr naming it and writes nothing;
# --work-precision refuses a passage over 20 s, and on a short one writes a CSV with a row for every
# integrator and CVODE whose default row (the exponential integrator) is more accurate than ROS2 at its
# default step, and which alone carries the error of the string force below 1 kHz and its errors over one
# tick; a failed row says why, and every row that ran counts its derivative evaluations.
set -u
hmp="$1"
demo="$2/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

bad_prefix=(sim "$demo" --track flute --from 10 --to 10.2)

# 1,000 notes at once (a 5 s chord): every tick of the window is in the CSV (the device's full inbox ran
# ticks the CSV missed), and the notes the device could not play as scheduled are said
python3 - "$tmp/chord.mid" <<'PY'
import struct, sys
ev = b"".join(b"\x00\x90" + bytes([24 + k % 84, 100]) for k in range(1000))
ev += b"\x83\x60" + b"\x80" + bytes([24, 0]) + b"".join(b"\x00\x80" + bytes([24 + k % 84, 0]) for k in range(1, 1000))
ev += b"\x00\xff\x2f\x00"
open(sys.argv[1], "wb").write(b"MThd" + struct.pack(">IHHH", 6, 0, 1, 96) + b"MTrk" + struct.pack(">I", len(ev)) + ev)
PY
"$hmp" sim "$tmp/chord.mid" --track 0 --to 1 --out "$tmp/chord.csv" 2>"$tmp/err"
check "1,000 notes at once: a row a tick" 1001 "$(wc -l <"$tmp/chord.csv")"
grep -q "warning: of 1000 notes the device started [0-9]* late" "$tmp/err" || { echo "FAIL: no word of late notes:"; cat "$tmp/err"; fail=1; }
rm -f "$tmp/chord.mid" "$tmp/chord.csv"

# A plant no integrator can carry (a grip of 10⁻³⁰⁰ kg): the values are at fault, exit 2, not "use exponential"
printf '[plant]\ngrip_mass = 1e-300\n' >"$tmp/tiny.toml"
expect_bad "unstable at 0.001 s under the default integrator: its values" --config "$tmp/tiny.toml"
rm -f "$tmp/tiny.toml"
# The config's [device] is the device simulated: its peak_force_n is --peak-force's default (it was ignored)
printf '[device]\npeak_force_n = 5\n' >"$tmp/peak.toml"
"$hmp" sim "$demo" --track flute --from 2 --to 2.5 --out "$tmp/default.csv" 2>/dev/null
"$hmp" sim "$demo" --track flute --from 2 --to 2.5 --config "$tmp/peak.toml" --out "$tmp/config.csv" 2>/dev/null
"$hmp" sim "$demo" --track flute --from 2 --to 2.5 --peak-force 5 --out "$tmp/option.csv" 2>/dev/null
cmp -s "$tmp/config.csv" "$tmp/option.csv" || { echo "FAIL: [device] peak_force_n = 5 is not --peak-force 5"; fail=1; }
cmp -s "$tmp/config.csv" "$tmp/default.csv" && { echo "FAIL: [device] peak_force_n had no effect"; fail=1; }
rm -f "$tmp/default.csv" "$tmp/config.csv" "$tmp/option.csv" "$tmp/peak.toml"

for v in 0 -1 nan inf 1e10; do
  expect_bad "string-stiffness" --string-stiffness "$v"
  expect_bad "max-step" --max-step "$v"
done
expect_bad "string-stiffness" --string-stiffness abc
# A max step so short that one tick would run for minutes (10⁻¹² s: 10⁹ steps a tick), from either side.
expect_bad "max-step: must be at least 1e-7 (got 1e-08)" --max-step 1e-8
printf '[plant]\nmax_step = 1e-12\n' >"$tmp/short.toml"
expect_bad "plant.max_step' must be at least 1e-7 s" --config "$tmp/short.toml"
expect_bad "string-stiffness: must be positive and at most 1e9 (got 2e+09)" --string-stiffness 2e9
expect_bad "integrator" --integrator bogus
printf '[plant]\nstring_stiffness = -5\n' >"$tmp/neg.toml"
expect_bad "plant.string_stiffness" --config "$tmp/neg.toml"
printf '[plant]\nstring_stifness = 1e5\n' >"$tmp/typo.toml"
expect_bad "plant.string_stifness" --config "$tmp/typo.toml"
printf '[plant]\nintegrator = "rk5"\n' >"$tmp/int.toml"
expect_bad "plant.integrator" --config "$tmp/int.toml"
"$hmp" sim "$demo" --track flute --from 10 --to 40 --work-precision >"$tmp/out" 2>"$tmp/err" </dev/null
rc=$?
{ [ $rc -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "at most 20 s" "$tmp/err"; } ||
  { echo "FAIL: a 30 s work-precision passage -> rc=$rc:"; cat "$tmp/err"; fail=1; }
[ -z "$(ls -A "$tmp" | grep -v '^out$\|^err$\|\.toml$')" ] || { echo "FAIL: something was written:"; ls -A "$tmp"; fail=1; }

# Stiff strings from the config, the integrator from the command line: a normal run.
printf '[plant]\nstring_stiffness = 1e6\ngrip_mass = 0.05\n' >"$tmp/stiff.toml"
"$hmp" sim "$demo" --track flute --from 10 --to 10.5 --config "$tmp/stiff.toml" --integrator rosenbrock2 \
  --max-step 1e-4 --out "$tmp/run.csv" 2>"$tmp/err" || { echo "FAIL: stiff run"; cat "$tmp/err"; fail=1; }
[ "$(wc -l <"$tmp/run.csv")" -gt 400 ] || { echo "FAIL: stiff run wrote too few rows"; fail=1; }

# Work-precision on a 0.2 s passage at 10⁵ N/m.
"$hmp" sim "$demo" --track flute --from 10 --to 10.2 --string-stiffness 1e5 --work-precision \
  --out "$tmp/wp.csv" 2>"$tmp/err" || { echo "FAIL: work-precision"; cat "$tmp/err"; fail=1; }
head -1 "$tmp/wp.csv" | grep -q '^integrator,steps_per_tick,rtol,default,ok,force_error_rel,finger_force_error_rel' ||
  { echo "FAIL: work-precision CSV header:"; head -1 "$tmp/wp.csv"; fail=1; }
for name in explicit_euler semi_implicit_euler rk4 linear_implicit_euler rosenbrock2 exponential cvode; do
  grep -q "^$name," "$tmp/wp.csv" || { echo "FAIL: no $name rows"; fail=1; }
done
awk -F, '$1 == "exponential" && $4 == 1 { e = $7 } $1 == "rosenbrock2" && $2 == 8 { r = $7 }
         END { if (!(e > 0 && r > 0 && e < r)) { print "FAIL: default " e " not below rosenbrock2 " r; exit 1 } }' \
  "$tmp/wp.csv" || fail=1
# The string force's error below 1 kHz: measured for the default, an empty field for the others.
awk -F, '$1 == "exponential" && $4 == 1 { b = $8 } $1 == "rk4" && $2 == 8 { o = $8; seen = 1 }
         END { if (!(b > 0) || !seen || o != "") { print "FAIL: band field default \"" b "\", rk4 \"" o "\""; exit 1 } }' \
  "$tmp/wp.csv" || fail=1
# The error over one tick: for the default a number below its bound, an empty field for the others.
awk -F, '$1 == "exponential" && $4 == 1 { t = $13; f = $14 } $1 == "rk4" && $2 == 8 { o = $13; seen = 1 }
         END { if (!(t > 0 && t < 0.01 && f > 0 && f < 0.005) || !seen || o != "") {
                 print "FAIL: one-tick fields default \"" t "\" \"" f "\", rk4 \"" o "\""; exit 1 } }' \
  "$tmp/wp.csv" || fail=1
# A failed run says why (explicit Euler at one step per tick is unstable on 10⁵ N/m strings); one that
# ran has an empty failure field.
awk -F, 'NR > 1 && $5 == 0 { failed++; if ($16 == "") { print "FAIL: row " NR " failed without a reason"; exit 1 } }
         NR > 1 && $5 == 1 && $16 != "" { print "FAIL: row " NR " ran but has failure " $16; exit 1 }
         $1 == "explicit_euler" && $2 == 1 && $16 != "unstable" { print "FAIL: explicit_euler 1: " $16; exit 1 }
         END { if (!failed) { print "FAIL: no failed row to check"; exit 1 } }' "$tmp/wp.csv" || fail=1
# The work done: every row that ran counts its derivatives, one that failed has an empty field, and
# classical Runge–Kutta takes four a step, so twice the steps take twice the derivatives to the unit.
awk -F, 'NR > 1 && $5 == 1 && !($15 > 0) { print "FAIL: row " NR " ran with derivatives \"" $15 "\""; exit 1 }
         NR > 1 && $5 == 0 && $15 != "" { print "FAIL: row " NR " failed with derivatives " $15; exit 1 }
         $1 == "rk4" { rk[$2] = $15 }
         END { if (!(rk[8] > 0 && rk[16] == 2 * rk[8])) { print "FAIL: rk4 derivatives " rk[8] ", " rk[16]; exit 1 } }' \
  "$tmp/wp.csv" || fail=1
exit $fail
