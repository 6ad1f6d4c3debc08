#!/usr/bin/env bash
# hmp play with several songs: files and folders in order (a folder's .mid/.midi files sorted by path,
# its subfolders' too), a file that cannot be read skipped with one line and exit 2 at the end, --loop
# until stopped, --shuffle playing each song once a pass, --track falling back per song; the log's
# per-song lines and its totals. On the simulated device with the virtual sound card, short passages.
set -u
hmp="$1"; repo="$2"
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
largo="$repo/examples/bach-bwv1079-trio-sonata-largo.mid"
pedal="$repo/examples/pedal-demo.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
play=(play --device sim --audio-driver virtual --no-view --from 1 --to 1.6)

# py LOG EXPR...: asserts on the log, read as `lines` (JSON), `ends` (song_end), `between` (between_songs),
# `started` and `summary`
py() {
  local log="$1"; shift
  /usr/bin/python3 - "$log" "$@" <<'PY' || fail=1
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
ends = [l["song_end"] for l in lines if "song_end" in l]
summary = [l["summary"] for l in lines if "summary" in l][-1]
started = [l for l in lines if "scheduled_tick" in l]
between = [l["between_songs"] for l in lines if "between_songs" in l]
for expr in sys.argv[2:]:
    if not eval(expr):
        print(f"FAIL: {expr}: ends {ends} summary {summary}")
        sys.exit(1)
PY
}

# --- files in order, each with its song_end line, the started lines naming their song
run "${play[@]}" "$demo" "$largo" --track 2 --log "$tmp/two.jsonl"  # both have violin notes in [1, 1.6) s
check "two files: exit" 0 "$rc"
check "two files: one summary line each, then the playlist's" 3 "$(wc -l <<<"$out")"
# The virtual card may run dry only because the machine woke its thread too late (the default 21 ms
# buffer; this VM's stalls reach 39 ms): checked below; said here, so that it is seen.
underruns=$(python3 -c 'import json,sys; print([json.loads(l)["summary"] for l in open(sys.argv[1]) if "summary" in l][-1]["audio_underruns"])' "$tmp/two.jsonl")
[ "$underruns" = 0 ] || echo "note: $underruns virtual-card underrun(s), each from the card thread waking late (a busy machine)"
grep -q '^\[1/2\] bach-bwv1050-brandenburg5-mvt3-allegro.mid: played' <<<"$out" || { echo "FAIL: no [1/2] line: $out"; fail=1; }
grep -q '^\[2/2\] bach-bwv1079-trio-sonata-largo.mid: played' <<<"$out" || { echo "FAIL: no [2/2] line: $out"; fail=1; }
py "$tmp/two.jsonl" '[e["index"] for e in ends] == [0, 1]' \
  "ends[1]['path'].endswith('largo.mid')" 'summary["songs_played"] == 2 and summary["files_skipped"] == 0' \
  'summary["notes_played"] == sum(e["notes_played"] for e in ends) > 0' \
  'sorted({l["song"] for l in started}) == [0, 1]' \
  'all(0.5 < e["played_s"] < 5 for e in ends)' 'isinstance(summary["audio_realtime"], bool)' \
  'len(summary["audio_underrun_list"]) == min(summary["audio_underruns"], 20)' \
  'all(u["woke_late_ms"] >= u["short_ms"] for u in summary["audio_underrun_list"])' \
  'len(between) == 2 and all(b["rss_kib"] > 1000 for b in between)' \
  'between[0]["wall_s"] <= ends[0]["wall_s"] <= between[1]["wall_s"] <= ends[1]["wall_s"]'  # before each song

# --- a folder: .mid and .MIDI and a subfolder's, sorted by path; other files left out
mkdir -p "$tmp/folder/sub" "$tmp/empty"
cp "$largo" "$tmp/folder/b.mid"; cp "$demo" "$tmp/folder/a.MIDI"; cp "$pedal" "$tmp/folder/sub/c.midi"
echo "not a song" >"$tmp/folder/notes.txt"
run "${play[@]}" "$tmp/folder" --log "$tmp/folder.jsonl"
check "folder: exit" 0 "$rc"
py "$tmp/folder.jsonl" "[e['path'].split('/folder/')[1] for e in ends] == ['a.MIDI', 'b.mid', 'sub/c.midi']"

# --- unreadable files are skipped with one line each; the others play; exit 2 says some were skipped
: >"$tmp/empty.mid"
run "${play[@]}" "$tmp/missing.mid" "$largo" "$tmp/empty.mid" "$tmp/empty" --log "$tmp/skip.jsonl"
check "skipped: exit" 2 "$rc"
check "skipped: one line per file" 2 "$(grep -c '^skipped ' <<<"$err")"
grep -q "^skipped $tmp/missing.mid: " <<<"$err" || { echo "FAIL: the missing file is not named: $err"; fail=1; }
grep -q "$tmp/empty: no .mid or .midi files" <<<"$err" || { echo "FAIL: the empty folder is not named: $err"; fail=1; }
grep -q "playlist: 1 song(s) played, 2 file(s) skipped" <<<"$out" || { echo "FAIL: playlist line: $out"; fail=1; }
py "$tmp/skip.jsonl" 'summary["songs_played"] == 1 and summary["files_skipped"] == 2' '[e["index"] for e in ends] == [1]'
# Nothing to play at all: one line, exit 2, before any device
bad_prefix=("${play[@]}")
expect_bad "no song to play: $tmp/empty: no .mid or .midi files" "$tmp/empty"
bad_prefix=()

# --- --track: a song that lacks it plays its default track (said); one song alone refuses it as before
run "${play[@]}" "$demo" "$pedal" --track violin --log "$tmp/track.jsonl"
check "--track in a playlist: exit" 0 "$rc"
grep -q "pedal-demo.mid: .*violin.*: the default track instead" <<<"$err" || { echo "FAIL: no fallback line: $err"; fail=1; }
bad_prefix=("${play[@]}")
expect_bad "violin" "$pedal" --track violin
bad_prefix=()

# --- --shuffle: each song once a pass, in some order
run "${play[@]}" "$demo" "$largo" "$pedal" --shuffle --log "$tmp/shuffle.jsonl"
check "--shuffle: exit" 0 "$rc"
py "$tmp/shuffle.jsonl" 'sorted(e["index"] for e in ends) == [0, 1, 2]'

# --- --loop: again from the first after the last, until stopped (Ctrl-C: exit 130, the log whole)
"$hmp" "${play[@]}" "$pedal" "$tmp/empty.mid" --loop --log "$tmp/loop.jsonl" </dev/null >"$tmp/out" 2>"$tmp/err" &
pid=$!
for _ in $(seq 150); do
  ends=$(cat "$tmp/loop.jsonl.part" 2>/dev/null | grep -c song_end)
  [ "$ends" -ge 3 ] && break
  sleep 0.1
done
kill -INT $pid; wait $pid; rc=$?
check "--loop: stopped by Ctrl-C" 130 "$rc"
py "$tmp/loop.jsonl" 'len(ends) >= 3' 'all(e["index"] == 0 for e in ends)' 'summary["songs_played"] == len(ends)' \
  'summary["notes_sent"] == summary["notes_played"] + summary["cancelled"]' \
  'all(e["cancelled"] == 0 for e in ends[:-1])' \
  'summary["files_skipped"] == 1'  # the empty file, skipped on every pass, is one file
grep -q '^\[1/2 pass 3\] pedal-demo.mid: played' "$tmp/out" || { echo "FAIL: no third pass: $(cat "$tmp/out")"; fail=1; }

# --- the audio buffer: whole periods of 256 frames at 48 kHz (19 × 5.33 ms for 100 ms), out of range refused
run "${play[@]}" "$pedal" --audio-buffer-ms 100
check "--audio-buffer-ms 100: exit" 0 "$rc"
grep -q 'output latency 101.3 ms' <<<"$err" || { echo "FAIL: --audio-buffer-ms 100: $err"; fail=1; }
expect_bad "audio-buffer-ms" play "$pedal" --audio-buffer-ms 5
expect_bad "audio-buffer-ms" play "$pedal" --audio-buffer-ms ten

exit $fail
