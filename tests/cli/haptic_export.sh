#!/usr/bin/env bash
# `hmp render SONG --track T --out FILE.ahap|.haptic` (docs/exports.md): a window in which no note of the
# track sounds is refused with one line naming the window, exit 2, and no file; a window with notes is
# written; the .haptic names the song by its file name (metadata source and description), not its path.
set -u
hmp=$(realpath "$1"); repo="$2"  # absolute: one run below starts in another directory
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"

# One track, 480 ticks per quarter at 120 bpm: key 60 from 0 to 1 s, key 62 from 3 to 4 s.
mkdir -p "$tmp/songs"
song="$tmp/songs/gap.mid"
printf 'MThd\x00\x00\x00\x06\x00\x00\x00\x01\x01\xe0MTrk\x00\x00\x00\x1e\x00\xff\x51\x03\x07\xa1\x20\x00\x90\x3c\x64\x87\x40\x80\x3c\x00\x8f\x00\x90\x3e\x64\x87\x40\x80\x3e\x00\x00\xff\x2f\x00' >"$song"

for ext in ahap haptic; do
  run render "$song" --track 0 --from 1.5 --to 2.5 --out "$tmp/silent.$ext"
  check "silent window .$ext: rc" 2 "$rc"
  check "silent window .$ext: one line" 1 "$(wc -l <<<"$err")"
  check "silent window .$ext: names the window" 1 "$(grep -c '1\.500–2\.500 s' <<<"$err")"
  check "silent window .$ext: nothing written" "no" "$([ -e "$tmp/silent.$ext" ] && echo yes || echo no)"

  run render "$song" --track 0 --from 0.5 --to 3.5 --out "$tmp/notes.$ext"
  check "window with notes .$ext: rc" 0 "$rc"
done

# Run from the songs' parent with a relative path: the metadata keeps the file name only.
(cd "$tmp" && "$hmp" render songs/gap.mid --track 0 --out "$tmp/named.haptic" 2>/dev/null)
check "metadata source" "gap.mid" "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["metadata"]["source"])' "$tmp/named.haptic")"
check "metadata description starts with the file name" "gap.mid — track 0" \
  "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["metadata"]["description"][:17])' "$tmp/named.haptic")"

[ "$fail" = 0 ] && echo "haptic export CLI: all checks passed"
exit "$fail"
