#!/usr/bin/env bash
# hmp calibrate: every bad input (a target or frequency out of range, a device that cannot be measured,
# a target out of reach) exits 2 with one line on stderr and writes nothing; a good run sets only
# [device] peak_force_n in the config, and replaces an existing file only with --force.
set -u
hmp="$1"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
cfg="$tmp/hmp.toml"

bad_prefix=(calibrate)

for t in 0 -1 nan inf 1000; do expect_bad "target-mm" --target-mm "$t" --config "$cfg"; done
for f in 49 251 0 nan inf -100; do expect_bad "frequency" --frequency "$f" --config "$cfg"; done
expect_bad "frequency" --frequency abc --config "$cfg"
expect_bad "only sim" --device hid --config "$cfg"
expect_bad "device" --device bogus --config "$cfg"
expect_bad "out of reach" --frequency 250 --config "$cfg"
expect_bad "out of reach" --target-mm 5 --frequency 100 --config "$cfg"
expect_bad "does not exist" --frequency 100 --config "$tmp/no/such/dir/hmp.toml"
[ -z "$(ls -A "$tmp" | grep -v '^out$\|^err$')" ] || { echo "FAIL: something was written:"; ls -A "$tmp"; fail=1; }
# Out of reach: the band's reach on stdout.
"$hmp" calibrate --frequency 250 >"$tmp/out" 2>/dev/null
grep -q "250 Hz" "$tmp/out" && grep -q " 50 Hz" "$tmp/out" || { echo "FAIL: no band table"; cat "$tmp/out"; fail=1; }

# A new file gets a [device] table with the key.
"$hmp" calibrate --frequency 100 --config "$cfg" >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: good run"; cat "$tmp/err"; fail=1; }
grep -q '^peak_force_n = 1[01]\.' "$cfg" || { echo "FAIL: new config:"; cat "$cfg"; fail=1; }

# The config's [plant] is the device measured: a lighter grip needs less force for the same 1 mm (the
# default plant's 10–11 N above), a bad [plant] value is refused like hmp sim refuses it.
printf '[plant]\ngrip_mass = 0.02\n' >"$tmp/light.toml"
"$hmp" calibrate --frequency 100 --config "$tmp/light.toml" --force >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: light grip"; cat "$tmp/err"; fail=1; }
grep -q '^peak_force_n = 9\.' "$tmp/light.toml" || { echo "FAIL: [plant] not measured:"; cat "$tmp/light.toml"; fail=1; }
printf '[plant]\nintegrator = "cvode"\n' >"$tmp/badplant.toml"
expect_bad "plant.integrator cvode: unknown" --frequency 100 --config "$tmp/badplant.toml" --force
grep -q peak_force_n "$tmp/badplant.toml" && { echo "FAIL: a bad [plant] was calibrated"; fail=1; }
# A tick rate the config allows but the band aliases at: refused, not "323643 mm at 200 Hz"
printf '[device]\ntick_hz = 100\n' >"$tmp/slow.toml"
expect_bad "slow.toml: \[device\] tick_hz 100: the band's 250 Hz is above 0.45 × the tick rate" --config "$tmp/slow.toml" --force
grep -q peak_force_n "$tmp/slow.toml" && { echo "FAIL: calibrated at 100 Hz ticks"; fail=1; }
rm -f "$tmp/light.toml" "$tmp/badplant.toml" "$tmp/slow.toml"

# An existing file: refused without --force (no terminal to ask), kept as it was.
printf '# my settings\n[mapping]\nmode = "paper"\n\n[device]\ntick_hz = 1000\npeak_force_n = 2.0  # old\n' >"$cfg"
before=$(md5sum <"$cfg")
expect_bad "exists" --frequency 100 --config "$cfg"
[ "$(md5sum <"$cfg")" = "$before" ] || { echo "FAIL: config modified without --force"; fail=1; }
expect_bad "directory" --frequency 100 --config "$tmp" --force
printf '[device]\nwobble = 3\n' >"$tmp/bad.toml"
expect_bad "unknown key" --frequency 100 --config "$tmp/bad.toml" --force

# With --force only the key's value changes; the old and new values are shown.
"$hmp" calibrate --frequency 100 --config "$cfg" --force >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: --force"; cat "$tmp/err"; fail=1; }
grep -q "peak_force_n: 2 N -> " "$tmp/out" || { echo "FAIL: old -> new not shown"; cat "$tmp/out"; fail=1; }
diff <(grep -v '^peak_force_n' "$cfg") <(printf '# my settings\n[mapping]\nmode = "paper"\n\n[device]\ntick_hz = 1000\n') \
  || { echo "FAIL: other lines changed"; fail=1; }
grep -q '^peak_force_n = 1[01]\.[0-9]*  # old$' "$cfg" || { echo "FAIL: key line:"; cat "$cfg"; fail=1; }

[ $fail -eq 0 ] && echo "calibrate: all passed"
exit $fail
