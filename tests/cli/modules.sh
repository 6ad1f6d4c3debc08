#!/usr/bin/env bash
# One program, back-ends loaded on demand (host/modules/, docs/host.md): hmp needs no shared library but
# the C library; each command loads only the modules — and through them the libraries — its work needs
# (the dynamic loader's own record, LD_DEBUG=files, lists every object loaded, dlopen included); a
# missing module is one warning (sound) or one error line naming it (a PNG), never a crash; and
# `cmake --install` gives a tree that still works after being moved.
set -u
hmp="$1"; repo="$2"
build=$(cd "$(dirname "$hmp")/.." && pwd)
demo="$repo/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
say_fail() { echo "FAIL: $*"; fail=1; }

# --- the program's own needs: the C library only (libstdc++ and libgcc are linked in)
needed=$(readelf -d "$hmp" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | grep -v '^ld-linux' | sort | tr '\n' ' ')
[ "$needed" = "libc.so.6 libm.so.6 " ] || say_fail "hmp needs more than the C library: $needed"

# loaded ARGS...: the shared objects hmp loaded running ARGS (file names, one a line).
loaded() {
  LD_DEBUG=files LD_DEBUG_OUTPUT="$tmp/ld" "$hmp" "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  sed -n 's/.*file=\([^ ]*\) .*\[0\];  \(needed\|dynamically loaded\) by.*/\1/p' "$tmp"/ld.* | xargs -n1 basename | sort -u
  rm -f "$tmp"/ld.*
  return $rc
}
heavy='fluidsynth|SDL2|cairo|asound|pulse|sndfile|samplerate|hidapi|usb-1\.0|GL|X11|wayland|avcodec|epoxy'
expect_light() {  # expect_light WHAT ARGS...: no module, none of the heavy libraries
  local what=$1; shift
  local libs; libs=$(loaded "$@") || { say_fail "$what: hmp $* failed"; cat "$tmp/err"; return; }
  if grep -Eq "hmp-|$heavy" <<<"$libs"; then say_fail "$what loaded: $(grep -E "hmp-|$heavy" <<<"$libs" | tr '\n' ' ')"; fi
  echo "ok: $what loads $(echo $libs)"
}
expect_light "info" info "$demo" --json
expect_light "render to CSV" render "$demo" --track flute --to 2 --out "$tmp/a.csv"
expect_light "play --no-audio --no-view on the simulated device" \
  play "$demo" --track flute --device sim --no-audio --no-view --from 30 --to 31
# Without a display the window is not even tried: the view module (SDL2, GL) stays out.
DISPLAY= WAYLAND_DISPLAY= expect_light "play --no-audio without a display" \
  play "$demo" --track flute --device sim --no-audio --from 30 --to 31

# The loader record can fail: a command that makes sound loads the audio module and FluidSynth with it.
libs=$(loaded play "$demo" --track flute --device sim --audio-driver virtual --no-view --from 30 --to 31) ||
  say_fail "play with the virtual card failed"
grep -q '^hmp-audio.so$' <<<"$libs" && grep -q 'libfluidsynth' <<<"$libs" ||
  say_fail "play with sound did not load hmp-audio.so and FluidSynth: $(echo $libs)"
grep -Eq 'cairo|hidapi|hmp-plot|hmp-usb' <<<"$libs" && say_fail "play with sound loaded plots or USB: $(echo $libs)"
libs=$(loaded render "$demo" --track flute --to 2 --out "$tmp/a.png") || say_fail "render to PNG failed"
grep -q '^hmp-plot.so$' <<<"$libs" && grep -q 'libcairo' <<<"$libs" || say_fail "render to PNG did not load cairo"
grep -Eq 'fluidsynth|hmp-audio' <<<"$libs" && say_fail "render to PNG loaded the audio module"

# --- without modules (HMP_MODULE_DIR pointing at an empty folder)
mkdir "$tmp/none"
HMP_MODULE_DIR="$tmp/none" "$hmp" play "$demo" --track flute --device sim --audio-driver virtual --no-view \
  --from 30 --to 31 --log "$tmp/log.jsonl" >"$tmp/out" 2>"$tmp/err"; rc=$?
warnings=$(grep -c "warning" "$tmp/err")
if [ $rc -ne 0 ] || [ "$warnings" -ne 1 ] || ! grep -q "warning: audio: the audio module is not available (.*hmp-audio.so" "$tmp/err"; then
  say_fail "play without the audio module: rc $rc, $warnings warning(s):"; cat "$tmp/err"
fi
grep -q '"summary"' "$tmp/log.jsonl" 2>/dev/null || say_fail "play without the audio module did not play"
HMP_MODULE_DIR="$tmp/none" "$hmp" render "$demo" --track flute --to 2 --out "$tmp/b.png" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ $rc -ne 2 ] || [ "$(wc -l <"$tmp/err")" -ne 1 ] || ! grep -q "b.png: PNG plots need the plot module" "$tmp/err"; then
  say_fail "render --out PNG without the plot module: rc $rc:"; cat "$tmp/err"
fi
[ -e "$tmp/b.png" ] && say_fail "a PNG was written without the plot module"
# A module from another build (here: not a module at all) is refused with its name, not loaded blindly.
cp /bin/true "$tmp/none/hmp-plot.so"
HMP_MODULE_DIR="$tmp/none" "$hmp" render "$demo" --track flute --to 2 --out "$tmp/c.png" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] && grep -q "hmp-plot.so" "$tmp/err" || { say_fail "a broken module: rc $rc"; cat "$tmp/err"; }

# --- cmake --install: bin/hmp + lib/hmp/*.so, relocatable
if cmake --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log" 2>&1; then
  mv "$tmp/prefix" "$tmp/moved"
  ln -s "$tmp/moved/bin/hmp" "$tmp/hmp-link"  # started through a symbolic link, as from /usr/local/bin
  "$tmp/hmp-link" render "$demo" --track flute --to 2 --out "$tmp/d.png" >"$tmp/out" 2>"$tmp/err" ||
    { say_fail "the installed, moved hmp could not draw a PNG"; cat "$tmp/err"; }
  ls "$tmp/moved/lib/hmp" | grep -q "hmp-audio.so" || say_fail "cmake --install did not install the modules"
else
  say_fail "cmake --install failed"; cat "$tmp/install.log"
fi

[ $fail -eq 0 ] && echo "ok: one program, modules on demand"
exit $fail
