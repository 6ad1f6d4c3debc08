#!/usr/bin/env bash
# midi-parse (design §4): hmp's MIDI reader against mido (parse + note pairing, timed inside Python; hmp's
# load_song timed inside a process too, by bench_midi_parse_inprocess) and midicsv (`midicsv FILE
# /dev/null` against the whole `hmp info --json` command), side by side on a generated large file
# (tools/bench/gen_big_midi.py: 12 tracks, 620k notes, ~1000 tempo changes, running status) and on the
# real songs (examples/*.mid and the Bach files of tests/data/midi/classical; identical files measured
# once). Also the peak RSS of `hmp info --json`. Run by scripts/bench with the build directory as $1.
# Needs midicsv and python3-mido (scripts/packages.txt).
set -euo pipefail
build=$1
# Building hmp builds its modules too (info loads none of them).
targets=(hmp bench_midi_parse_inprocess)
# A tree configured before tools/bench/midi_parse_inprocess.cpp existed does not know its target yet.
cmake --build "$build" -j2 --target "${targets[@]}" >&2 ||
  { cmake "$build" >&2 && cmake --build "$build" -j2 --target "${targets[@]}" >&2; }

# The generated file is cached in the build tree and made again when the generator changes.
notes=620000
big="$build/bench/midi-parse-big-$notes.mid"
if [ ! -f "$big" ] || [ tools/bench/gen_big_midi.py -nt "$big" ]; then
  mkdir -p "$build/bench"
  echo "midi-parse: generating $big" >&2
  /usr/bin/python3 tools/bench/gen_big_midi.py "$big.tmp" --notes "$notes" && mv "$big.tmp" "$big"
fi

files=("generated-big.mid=$big")
seen=()
for f in examples/*.mid tests/data/midi/classical/*.mid; do
  [ -f "$f" ] || continue
  sum=$(cksum < "$f" | tr " " _)
  if [[ " ${seen[*]-} " == *" $sum "* ]]; then
    echo "midi-parse: $f is a copy of a file already measured; skipped" >&2
    continue
  fi
  seen+=("$sum")
  files+=("$f")
done
exec /usr/bin/python3 tools/bench/midi_parse.py "$build/bin/hmp" "$build/bench/bench_midi_parse_inprocess" "${files[@]}"
