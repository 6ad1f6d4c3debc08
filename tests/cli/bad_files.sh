#!/usr/bin/env bash
# Files the user names, on the command line (design §2): a directory given where a file is read says so
# (song, --config, --soundfont, --firmware, study results); an existing output is kept without --force
# and replaced with it, and no PATH.part is left behind; an output folder that does not exist fails before
# anything is printed; a results file with a spreadsheet's byte order mark is read; a NUL or bytes that
# are not UTF-8 are escaped in the message, and a version that is not UTF-8 is refused; a damaged song
# refused says how many warnings its reading gave, not the warnings. Each bad case:
# exit 2, one line on stderr, nothing on stdout.
set -u
hmp="$1"; repo="$2"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

expect_exact_error() {  # expect_exact_error EXACT-STDERR ARGS...
  local want="$1"; shift
  "$hmp" "$@" >"$tmp/out" 2>"$tmp/err"; local rc=$?
  local err; err=$(<"$tmp/err")
  if [ $rc -ne 2 ] || [ "$err" != "$want" ] || [ -s "$tmp/out" ]; then
    echo "FAIL: hmp $* -> rc=$rc, stdout $(wc -c <"$tmp/out") bytes, wanted [$want], stderr:"; cat -v "$tmp/err"; fail=1
  fi
}
echo old >"$tmp/old"
is_old() { cmp -s "$1" "$tmp/old"; }  # is_old FILE: FILE still holds "old"
no_part() {  # no_part FILE: no FILE.part left behind
  if [ -e "$1.part" ]; then echo "FAIL: $1.part left behind"; fail=1; fi
}

dir="$tmp/a folder"
mkdir "$dir"

# --- a directory where a file is read
expect_exact_error "error: $dir: is a directory" info "$dir"
expect_exact_error "error: $dir: is a directory" render "$dir" --track 1 --out "$tmp/x.csv"
expect_exact_error "error: $dir: is a directory" render "$demo" --track flute --config "$dir" --out "$tmp/x.csv"
expect_exact_error "error: $dir: is a directory" render "$demo" --sound --soundfont "$dir" --out "$tmp/x.wav"
expect_exact_error "error: $dir: is a directory" play "$demo" --no-audio --soundfont "$dir"
expect_exact_error "error: $dir: is a directory" study analyze "$dir"
expect_exact_error "error: $dir: is a directory" flash --dry-run --firmware "$dir"
expect_exact_error "error: $tmp/none.csv: no such file" study analyze "$tmp/none.csv"
expect_exact_error "error: $tmp/none.toml: no such file" render "$demo" --track flute --config "$tmp/none.toml" --out "$tmp/x.csv"
[ -e "$tmp/x.csv" ] && { echo "FAIL: x.csv written"; fail=1; }

# --- a damaged song refused: its one error line counts the reader's warnings instead of printing them;
# accepted, its warnings come first. The demo's first 300 bytes: a cut track, 9 tracks announced, 2 there.
head -c 300 "$demo" >"$tmp/cut.mid"
counted="; reading the file gave 3 warnings (hmp info lists them)"
expect_exact_error "error: --track 5: no such track (0–1)$counted" render "$tmp/cut.mid" --track 5 --out "$tmp/x.csv"
expect_exact_error "error: --track 5: no such track (0–1)$counted" sim "$tmp/cut.mid" --track 5 --out "$tmp/x.csv"
expect_exact_error "error: --track 5: no such track (0–1)$counted" play "$tmp/cut.mid" --track 5 --no-audio --no-view
expect_exact_error "error: --track 5: no such track (0–1)$counted" view "$tmp/cut.mid" --track 5
expect_exact_error "error: --from 400: the song's sound ends at 312.000 s (2 s after its last event)$counted" \
  render "$tmp/cut.mid" --sound --from 400 --out "$tmp/x.wav"
expect_ok render "$tmp/cut.mid" --track 1 --to 1 --out "$tmp/x.csv"
[ "$(grep -c '^warning: ' "$tmp/err")" = 3 ] || { echo "FAIL: a damaged song rendered without its 3 warnings"; fail=1; }
rm -f "$tmp/x.csv"

# --- what the user typed or a config held, quoted in the error line: a control character escaped, not
# sent to the terminal; 100,000 bytes cut to a line with the rest counted
expect_exact_error "error: --mapping a\x01b: unknown (paper, rank, constant, legacy2013)" info "$demo" --mapping "a$(printf '\001')b"
expect_exact_error "error: --zoom: \x1B[2J is not a number from 1 to 120 (try --help)" render "$demo" --zoom "$(printf '\033')[2J"
{ printf '[envelope]\ndefault = "'; head -c 100000 /dev/zero | tr '\0' y; printf '"\n'; } >"$tmp/long.toml"
"$hmp" info "$demo" --config "$tmp/long.toml" >"$tmp/out" 2>"$tmp/err"
[ "$(wc -l <"$tmp/err")" = 1 ] && [ "$(wc -c <"$tmp/err")" -lt 1100 ] && grep -q 'bytes more)$' "$tmp/err" ||
  { echo "FAIL: a 100,000-byte preset name: $(wc -c <"$tmp/err") bytes of error"; fail=1; }

# --- a results file: one participant's main rounds of experiment 1
results() {  # results VERSION: the file's text on stdout
  echo "participant,experiment,phase,position,instrument,mapping,envelope,key,rank,seconds_felt,times_selected,round_started_utc,ranked_utc,round_ended_utc,seed,version"
  local pos=0
  for inst in flute violin contrabass harpsichord; do
    pos=$((pos + 1)); local k=0
    for env in square triangle analogue; do
      printf 'p1,1,main,%d,%s,paper,%s,%d,%d,1.000,1,2026-11-24T19:37:07.250Z,2026-11-24T19:37:17.250Z,2026-11-24T19:37:18.250Z,5,%s\n' \
        "$pos" "$inst" "$env" "$k" "$((k + 1))" "$1"
      k=$((k + 1))
    done
  done
}
results "1.0" >"$tmp/r.csv"
expect_ok study analyze "$tmp/r.csv"
grep -q "flute" "$tmp/out" || { echo "FAIL: analyze printed no table"; fail=1; }

# A spreadsheet's "CSV UTF-8": a byte order mark first, Windows line ends.
{ printf '\xEF\xBB\xBF'; results "1.0" | sed 's/$/\r/'; } >"$tmp/bom.csv"
expect_ok study analyze "$tmp/bom.csv"
cmp -s "$tmp/out" <("$hmp" study analyze "$tmp/r.csv" 2>/dev/null) || { echo "FAIL: the BOM file reads differently"; fail=1; }

# A NUL and bytes that are not UTF-8: escaped in the one-line message; a non-UTF-8 version refused.
results "1.0" | sed '2s/^p1,/p\x001,/' >"$tmp/nul.csv"
expect_exact_error "error: $tmp/nul.csv:2: bad participant id \"p\\01\"" study analyze "$tmp/nul.csv"
results "v$(printf '\xff')1" >"$tmp/latin.csv"
expect_exact_error "error: $tmp/latin.csv:2: version \"v\\xFF1\" is not valid UTF-8" study analyze "$tmp/latin.csv"
results "1.0" | sed "2s/,flute,/,fl$(printf '\xe9')te,/" >"$tmp/inst.csv"
expect_exact_error "error: $tmp/inst.csv:2: instrument \"fl\\xE9te\" is not valid UTF-8" study analyze "$tmp/inst.csv"

# --- the study figure: checked before the table is printed; kept without --force
expect_exact_error "error: $tmp/missing/fig.png: folder $tmp/missing does not exist" study analyze "$tmp/r.csv" --out "$tmp/missing/fig.png"
expect_exact_error "error: --out -: the figure needs a file name" study analyze "$tmp/r.csv" --out -
echo old >"$tmp/fig.png"
expect_exact_error "error: $tmp/fig.png: file exists (use --force to overwrite)" study analyze "$tmp/r.csv" --out "$tmp/fig.png" </dev/null
is_old "$tmp/fig.png" || { echo "FAIL: fig.png overwritten without --force"; fail=1; }
no_part "$tmp/fig.png"
expect_exact_error "error: $dir: is a directory" study analyze "$tmp/r.csv" --out "$dir"
if "$hmp" study analyze "$tmp/r.csv" --out "$tmp/fig.png" --force >"$tmp/out" 2>"$tmp/err"; then
  [ "$(head -c 4 "$tmp/fig.png" | od -An -tx1 | tr -d ' ')" = 89504e47 ] || { echo "FAIL: --force did not write a PNG"; fail=1; }
  no_part "$tmp/fig.png"
elif grep -q "plot module" "$tmp/err"; then
  echo "note: no plot module in this build; the --force replacement is not checked"
else
  echo "FAIL: study analyze --force: $(cat "$tmp/err")"; fail=1
fi

# --- every writer of a user-named output: kept without --force, replaced with it, no .part left
for ext in csv wav png ahap haptic; do
  out="$tmp/track.$ext"
  echo old >"$out"
  expect_exact_error "error: $out: file exists (use --force to overwrite)" render "$demo" --track flute --to 8 --out "$out" </dev/null
  is_old "$out" || { echo "FAIL: $out overwritten without --force"; fail=1; }
  expect_ok render "$demo" --track flute --to 8 --out "$out" --force
  ! is_old "$out" && [ -s "$out" ] || { echo "FAIL: $out not replaced with --force"; fail=1; }
  no_part "$out"
  expect_exact_error "error: $tmp/nowhere/track.$ext: folder $tmp/nowhere does not exist" render "$demo" --track flute --to 8 --out "$tmp/nowhere/track.$ext"
done
for ext in csv png; do
  out="$tmp/sim.$ext"
  echo old >"$out"
  expect_exact_error "error: $out: file exists (use --force to overwrite)" sim "$demo" --track flute --to 8 --out "$out" </dev/null
  is_old "$out" || { echo "FAIL: $out overwritten without --force"; fail=1; }
  expect_ok sim "$demo" --track flute --to 8 --out "$out" --force
  ! is_old "$out" || { echo "FAIL: $out not replaced with --force"; fail=1; }
  no_part "$out"
done
out="$tmp/tone.wav"
echo old >"$out"
expect_exact_error "error: $out: file exists (use --force to overwrite)" tone --freq 100 --amp 0.5 --ms 50 --instrument flute --out "$out" </dev/null
expect_ok tone --freq 100 --amp 0.5 --ms 50 --instrument flute --out "$out" --force
[ "$(head -c 4 "$out")" = RIFF ] || { echo "FAIL: tone --force did not write a WAV"; fail=1; }
no_part "$out"
out="$tmp/sound.wav"
echo old >"$out"
expect_exact_error "error: $out: file exists (use --force to overwrite)" render "$demo" --sound --to 1 --out "$out" </dev/null
expect_ok render "$demo" --sound --to 1 --out "$out" --force
[ "$(head -c 4 "$out")" = RIFF ] || { echo "FAIL: render --sound --force did not write a WAV"; fail=1; }
no_part "$out"
# --- a FILE.part already there (a run cut short, or the user's): kept, and a link there not written
# through, without --force; replaced by our own file with it
echo victim >"$tmp/victim.txt"
for ext in csv wav png haptic; do
  out="$tmp/staged.$ext"
  echo precious >"$out.part"
  expect_exact_error "error: $out.part: exists, the temporary name of $out (use --force to replace it)" render "$demo" --track flute --to 8 --out "$out" </dev/null
  [ "$(cat "$out.part")" = precious ] || { echo "FAIL: $out.part overwritten without --force"; fail=1; }
  rm "$out.part"; ln -s "$tmp/victim.txt" "$out.part"
  expect_ok render "$demo" --track flute --to 8 --out "$out" --force
  [ "$(cat "$tmp/victim.txt")" = victim ] || { echo "FAIL: $out written through a link at $out.part"; fail=1; }
  [ -f "$out" ] && [ ! -L "$out" ] || { echo "FAIL: $out is not a file of its own"; fail=1; }
  no_part "$out"
done
rm "$tmp/victim.txt"
ls "$tmp" | grep -q '\.part$' && { echo "FAIL: .part files left: $(ls "$tmp" | grep '\.part$')"; fail=1; }

exit $fail
