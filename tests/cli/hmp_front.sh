#!/usr/bin/env bash
# The static front `hmp` (host/cli/front_main.cpp) against hmp-full, the program with every command: the
# command lines the front runs itself print the same bytes and exit codes as hmp-full; everything else is
# handed to hmp-full intact; the front is statically linked; without hmp-full beside it, commands other
# than info fail with one line naming the missing file.
set -u
hmp="$1"; repo="$2"
full="$(dirname "$hmp")/hmp-full"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
corpus="$repo/tests/data/midi"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0

# run NAME PROGRAM ARGS...: stdout, stderr and exit code to $tmp/NAME.{out,err,rc}, argv[0] "hmp" for both
# programs (CLI11 puts argv[0] into its usage lines).
run() {
  local name="$1" program="$2"; shift 2
  (exec -a hmp "$program" "$@") >"$tmp/$name.out" 2>"$tmp/$name.err"
  echo $? >"$tmp/$name.rc"
}
same() {  # same ARGS...: the front and hmp-full agree byte for byte
  run front "$hmp" "$@"
  run full "$full" "$@"
  local part
  for part in out err rc; do
    if ! cmp -s "$tmp/front.$part" "$tmp/full.$part"; then
      echo "FAIL: hmp $*: the front's std$part differs from hmp-full's"
      diff <(head -c 2000 "$tmp/front.$part") <(head -c 2000 "$tmp/full.$part") | head -8
      fail=1
    fi
  done
}

[ -x "$full" ] || { echo "FAIL: no hmp-full next to $hmp"; exit 1; }

# --- what the front runs itself: info in every plain form, --version
same info --json "$demo"
same info "$demo" --json --notes
same info --notes --json "$demo"
same info "$demo"
same --version
grep -q '^hmp [0-9]' "$tmp/front.out" || { echo "FAIL: --version printed '$(cat "$tmp/front.out")'"; fail=1; }
# The whole corpus: good files, warnings and broken ones (their one-line errors and exit code 2).
files=0
while IFS= read -r -d '' f; do
  same info --json "$f"
  files=$((files + 1))
done < <(find "$corpus" -iname '*.mid' -print0 | sort -z)
[ "$files" -ge 10 ] || { echo "FAIL: only $files corpus files under $corpus"; fail=1; }
same info "$tmp/missing.mid"
printf 'hello, not midi' >"$tmp/junk.mid"
same info --json "$tmp/junk.mid"
[ "$(cat "$tmp/front.rc")" = 2 ] && [ "$(wc -l <"$tmp/front.err")" = 1 ] ||
  { echo "FAIL: a junk file: rc $(cat "$tmp/front.rc"), $(wc -l <"$tmp/front.err") stderr lines"; fail=1; }
# Song names that look like commands or flags' neighbours are still songs.
same info play
same info info --json

# --- what the front hands to hmp-full: other commands, help, command-line errors
same --help
grep -q '^ *play ' "$tmp/front.out" || { echo "FAIL: hmp --help does not list play"; fail=1; }
same info --help
same
same info
same info --json
same info a.mid b.mid
same info --json --json "$demo"
same info --bogus "$demo"
same nosuchcommand
same tone --freq 100 --amp 0.5 --ms 30 --instrument organ --out -
[ "$(wc -l <"$tmp/front.out")" -gt 10 ] || { echo "FAIL: tone through the front printed too little"; fail=1; }
same render "$demo" --track flute --from 2 --to 2.5 --out -
[ "$(wc -l <"$tmp/front.out")" -gt 100 ] || { echo "FAIL: render through the front printed too little"; fail=1; }

# --- statically linked: no program interpreter, no shared object needed. Under the sanitizers (the asan
# preset) the front is dynamic on purpose (g++ refuses -static with ASan): then only say so.
if readelf -dW "$hmp" | grep -q 'NEEDED.*libasan'; then
  echo "note: sanitizer build, the front is dynamic; static check skipped"
else
  if readelf -lW "$hmp" | grep -q 'INTERP'; then echo "FAIL: the front has a program interpreter"; fail=1; fi
  if readelf -dW "$hmp" | grep -q 'NEEDED'; then
    echo "FAIL: the front needs shared objects:"; readelf -dW "$hmp" | grep NEEDED; fail=1
  fi
  readelf -hW "$hmp" | grep -q 'Type: *EXEC' || { echo "FAIL: the front is not a plain executable"; fail=1; }
fi

# --- alone, without hmp-full: info still works (it really runs in the front), the rest fails cleanly
mkdir "$tmp/alone"
cp "$hmp" "$tmp/alone/hmp"
run alone "$tmp/alone/hmp" info --json "$demo"
run full "$full" info --json "$demo"
cmp -s "$tmp/alone.out" "$tmp/full.out" && [ "$(cat "$tmp/alone.rc")" = 0 ] ||
  { echo "FAIL: hmp info without hmp-full beside it: rc $(cat "$tmp/alone.rc")"; cat "$tmp/alone.err"; fail=1; }
run alone "$tmp/alone/hmp" play "$demo"
if [ "$(cat "$tmp/alone.rc")" != 2 ] || [ "$(wc -l <"$tmp/alone.err")" != 1 ] ||
   ! grep -q "$tmp/alone/hmp-full" "$tmp/alone.err" || [ -s "$tmp/alone.out" ]; then
  echo "FAIL: hmp play without hmp-full: rc $(cat "$tmp/alone.rc"), stderr:"; cat "$tmp/alone.err"; fail=1
fi

[ $fail -eq 0 ] && echo "ok: front and hmp-full agree ($files corpus files)"
exit $fail
