#!/usr/bin/env bash
# hmp study --age/--sex/--handedness: a bad value, or a participant resumed with other values than the
# results file holds, exits 2 with one line on stderr and writes nothing; `study analyze` prints the
# participants' summary before the statistics, also for a file written before these columns existed.
set -u
hmp="$1"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

expect_refused_untouched() {  # expect_refused_untouched WORD-IN-MESSAGE DIR ARGS...: refused before anything is written in DIR
  local word="$1" dir="$2"; shift 2
  local before; before=$(ls -l --time-style=full-iso "$dir"; cat "$dir"/* 2>/dev/null | md5sum)
  "$hmp" study --device sim --no-audio --out "$dir" "$@" </dev/null >"$tmp/out" 2>"$tmp/err"; local rc=$?
  local lines; lines=$(wc -l <"$tmp/err")
  if [ $rc -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -qF -- "$word" "$tmp/err"; then
    echo "FAIL: study $* -> rc=$rc, $lines stderr line(s), wanted '$word':"; cat "$tmp/err"; fail=1
  fi
  [ "$(ls -l --time-style=full-iso "$dir"; cat "$dir"/* 2>/dev/null | md5sum)" = "$before" ] || {
    echo "FAIL: study $* changed $dir:"; ls -l "$dir"; fail=1; }
}

mkdir "$tmp/empty"
expect_refused_untouched "--age 4: whole years from 5 to 120" "$tmp/empty" --participant p --age 4
expect_refused_untouched "--age 121: whole years from 5 to 120" "$tmp/empty" --participant p --age 121
expect_refused_untouched "--age 30.5:" "$tmp/empty" --participant p --age 30.5
expect_refused_untouched "--age -3:" "$tmp/empty" --participant p --age=-3
expect_refused_untouched "--age x:" "$tmp/empty" --participant p --age x
expect_refused_untouched "--sex f: female, male, other or unstated" "$tmp/empty" --participant p --sex f
expect_refused_untouched "--handedness both: left, right, ambidextrous or unstated" "$tmp/empty" --participant p --handedness both
[ -z "$(ls "$tmp/empty")" ] || { echo "FAIL: files written for bad options: $(ls "$tmp/empty")"; fail=1; }

# A participant with one finished round (seed 1; age 30, female, right-handed): other values refused.
times="2026-01-01T10:00:00.000Z,2026-01-01T10:00:05.000Z,2026-01-01T10:00:09.000Z"
round_cols="participant,experiment,phase,position,instrument,mapping,envelope,key,rank,seconds_felt,times_selected,round_started_utc,ranked_utc,round_ended_utc,seed,version"
mkdir "$tmp/new"
{
  echo "$round_cols,age,sex,handedness"
  echo "p,1,main,1,flute,paper,square,0,3,3.000,1,$times,1,hmp,30,female,right"
  echo "p,1,main,1,flute,paper,triangle,1,2,3.000,1,$times,1,hmp,30,female,right"
  echo "p,1,main,1,flute,paper,analogue,2,1,3.000,1,$times,1,hmp,30,female,right"
} >"$tmp/new/study-results.csv"
expect_refused_untouched "participant p: age 31, but 30 on $tmp/new/study-results.csv:2" "$tmp/new" --participant p --seed 1 --age 31
expect_refused_untouched "participant p: sex male, but female on" "$tmp/new" --participant p --seed 1 --age 30 --sex male
expect_refused_untouched "handedness left, but right" "$tmp/new" --participant p --seed 1 --handedness left
[ ! -e "$tmp/new/study-p.journal" ] || { echo "FAIL: a refused session wrote its journal"; fail=1; }
# The same with the session's journal there, as when resuming for real: still the error alone.
printf 'seed=1\nexperiments=both\n' >"$tmp/new/study-p.journal"
expect_refused_untouched "participant p: age 29, but 30 on" "$tmp/new" --participant p --age 29 --sex female

"$hmp" study analyze "$tmp/new/study-results.csv" >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: analyze"; cat "$tmp/err"; fail=1; }
expected="participants: 1 — sex: female 1, male 0, other 0, unstated 0
age: 30–30 years, mean 30.0 (all 1 gave it)
handedness: left 0, right 1, ambidextrous 0, unstated 0

experiment 1 (paper mapping), flute: 1 participant(s)"
[ "$(head -5 "$tmp/out")" = "$expected" ] || { echo "FAIL: analyze output:"; cat "$tmp/out"; fail=1; }

# A file from before the participant's columns: analysed; it has no room for them, so they are refused.
mkdir "$tmp/old"
{
  echo "$round_cols"
  echo "q,1,main,1,flute,paper,square,0,3,3.000,1,$times,1,hmp"
  echo "q,1,main,1,flute,paper,triangle,1,2,3.000,1,$times,1,hmp"
  echo "q,1,main,1,flute,paper,analogue,2,1,3.000,1,$times,1,hmp"
} >"$tmp/old/study-results.csv"
expect_refused_untouched "written before the age, sex and handedness columns" "$tmp/old" --participant r --sex female
"$hmp" study analyze "$tmp/old/study-results.csv" >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: analyze old"; cat "$tmp/err"; fail=1; }
grep -qxF "age: not given (by none of the 1)" "$tmp/out" || { echo "FAIL: old file's summary:"; cat "$tmp/out"; fail=1; }
grep -qF "Copeland winner: analogue" "$tmp/out" || { echo "FAIL: old file's analysis:"; cat "$tmp/out"; fail=1; }

# Rows of one participant that disagree: the file is refused with its line.
sed -i '4s/,30,female,right$/,31,female,right/' "$tmp/new/study-results.csv"
"$hmp" study analyze "$tmp/new/study-results.csv" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] && [ "$(cat "$tmp/err")" = "error: $tmp/new/study-results.csv:4: participant p: age 31, but 30 on line 2" ] || {
  echo "FAIL: disagreeing rows -> rc=$rc:"; cat "$tmp/err"; fail=1; }

[ $fail -eq 0 ] && echo "study_participant: all passed"
exit $fail
