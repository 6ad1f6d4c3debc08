#!/usr/bin/env bash
# The install is relocatable and carries no path of the build machine (cmake/install.cmake,
# host/common/install_layout.hpp): `cmake --install` of this build tree into a scratch prefix, the prefix
# moved elsewhere, the source tree hidden under an empty tmpfs in a private mount namespace, and then
# `hmp info`, `hmp render … --out x.png`, `hmp play --no-audio --no-view` and `hmp flash --dry-run` run
# from the moved tree and find its examples and firmware image. Then without the modules whose libraries
# a headless machine lacks (audio, window, video): info, render to CSV and play --no-audio --no-view still work.
# The program and its modules, installed, hold neither the source tree's nor the build tree's path.
# Usage: install.sh HMP REPO (HMP in <build>/bin/).
hmp_built="$1"; repo="$2"; hmp="$1"
source "$(dirname "$0")/lib.bash"
build=$(cd "$(dirname "$hmp_built")/.." && pwd)
case "$tmp" in "$repo"/*) echo "FAIL: the scratch folder $tmp is inside the source tree"; exit 1 ;; esac

if ! cmake --install "$build" --prefix "$tmp/first" >"$tmp/install.log" 2>&1; then
  echo "FAIL: cmake --install"; cat "$tmp/install.log"; exit 1
fi
mv "$tmp/first" "$tmp/moved"
p="$tmp/moved"
version=$("$hmp_built" --version | awk '{print $2}')
for f in bin/hmp lib/hmp/hmp-audio.so lib/hmp/hmp-plot.so lib/udev/rules.d/70-hmp.rules \
         share/hmp/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid share/man/man1/hmp-play.1.gz \
         share/bash-completion/completions/hmp share/doc/hmp/copyright \
         share/hmp/firmware/hmp_fw_stm32f407-$version.bin share/hmp/firmware/hmp_fw_stm32f407-$version.dfu \
         share/hmp/firmware/hmp_fw_qemu_an386-$version.elf; do
  [ -f "$p/$f" ] || { echo "FAIL: not installed: $f"; fail=1; }
done

# No path of this machine in what runs: the source tree (the build tree is inside it with the presets,
# and is checked on its own when it is not).
for dir in "$repo" "$build"; do
  if hits=$(grep -rlF -- "$dir" "$p/bin" "$p/lib/hmp"); then
    echo "FAIL: $dir is in the installed $(echo $hits)"; fail=1
  fi
done

# From the moved prefix, the source tree hidden. A mount namespace needs root or user namespaces. Its
# mounts are made private inside (below), not by unshare: in a chroot "/" is no mount point and unshare's
# own --propagation private fails there.
unshare_cmd=(unshare --mount --propagation unchanged)
[ "$(id -u)" -eq 0 ] || unshare_cmd=(unshare --mount --map-root-user --propagation unchanged)
if ! "${unshare_cmd[@]}" true 2>/dev/null; then
  echo "SKIPPED: no private mount namespace here (unshare): the source tree cannot be hidden"
  exit 77
fi
song="$p/share/hmp/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid"
cat >"$tmp/hidden.sh" <<SCRIPT
set -u
# The tmpfs must not reach the parent namespace: every mount made private, or (in a chroot, where "/" is
# no mount point) the tree bound onto itself and that mount made private.
if ! mount --make-rprivate / 2>/dev/null; then
  mount --bind "$repo" "$repo" && mount --make-private "$repo" || exit 89
fi
mount -t tmpfs none "$repo" || exit 90
[ -z "\$(ls -A "$repo")" ] || exit 91
cd "$tmp"
unset HMP_SOURCE_DIR HMP_QEMU_ELF
"$p/bin/hmp" info "$song" >info.txt 2>&1 || echo "info \$?" >>failed
"$p/bin/hmp" render "$song" --track flute --to 4 --out x.png >render.txt 2>&1 || echo "render \$?" >>failed
"$p/bin/hmp" play "$song" --no-audio --no-view --to 3 >play.txt 2>&1 || echo "play \$?" >>failed
"$p/bin/hmp" flash --dry-run --method dfu >flash.txt 2>&1 || echo "flash \$?" >>failed
rm -f "$p"/lib/hmp/hmp-audio.so "$p"/lib/hmp/hmp-view.so "$p"/lib/hmp/hmp-video.so
"$p/bin/hmp" info "$song" >headless-info.txt 2>&1 || echo "headless info \$?" >>failed
"$p/bin/hmp" render "$song" --track flute --to 4 --out headless.csv >headless-render.txt 2>&1 || echo "headless render \$?" >>failed
"$p/bin/hmp" play "$song" --no-audio --no-view --to 3 >headless-play.txt 2>&1 || echo "headless play \$?" >>failed
exit 0
SCRIPT
"${unshare_cmd[@]}" bash "$tmp/hidden.sh"; rc=$?
if [ $rc -eq 89 ]; then
  echo "SKIPPED: no private mount could be made here for the source tree: not hidden"
  exit 77
fi
check "the source tree hidden (rc)" 0 "$rc"
if [ -f "$tmp/failed" ]; then
  echo "FAIL: from the moved tree: $(tr '\n' ';' <"$tmp/failed")"
  for f in "$tmp"/*.txt; do echo "--- $(basename "$f")"; cat "$f"; done
  fail=1
fi
grep -q "6006 note(s)" "$tmp/info.txt" || { echo "FAIL: info did not read the installed song"; fail=1; }
[ "$(head -c 8 "$tmp/x.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || { echo "FAIL: x.png is no PNG"; fail=1; }
grep -q "^played [1-9]" "$tmp/play.txt" || { echo "FAIL: play played nothing: $(<"$tmp/play.txt")"; fail=1; }
check "flash uses the installed image" \
  "dfu-util -d 0483:df11 -a 0 -s 0x08000000:leave -D $p/share/hmp/firmware/hmp_fw_stm32f407-$version.bin" \
  "$(<"$tmp/flash.txt")"
[ "$(head -n 1 "$tmp/headless.csv")" = t_s,value ] || { echo "FAIL: headless.csv: $(head -n 2 "$tmp/headless.csv")"; fail=1; }
grep -q "^played [1-9]" "$tmp/headless-play.txt" || { echo "FAIL: headless play: $(<"$tmp/headless-play.txt")"; fail=1; }
exit $fail
