#!/usr/bin/env bash
# Makes the Linux guest of the USB tests (docs/usb.md, "Linux guest test") in CACHE_DIR:
#   vmlinuz          Debian 12's own kernel (the package linux-image-amd64 depends on), downloaded with
#                    `apt-get download` and unpacked with `dpkg-deb -x` — never installed on this system;
#   modules/         the modules the guest loads, in order: usb-common usbcore xhci-hcd xhci-pci hid usbhid
#                    hid-generic (their dependencies read from each module's .modinfo);
# and, for every run, an initramfs with busybox-static, those modules, an init that loads them and runs
# GUEST_SCRIPT, and the extra files given (programs with the shared libraries `ldd` names).
#
# usage: guest-image.sh CACHE_DIR OUT_INITRAMFS GUEST_SCRIPT [PROGRAM | SRC=GUEST_PATH]...
#   PROGRAM goes to /opt/bin (stripped) with its libraries; SRC=GUEST_PATH copies a data file, or a shared
#   object (*.so: an hmp module) stripped and with its libraries.
# Prints nothing on success but what it downloads; exits 1 with one line saying what failed.
set -euo pipefail
cache=$1 out=$2 script=$3
shift 3
modules=(usb-common usbcore xhci-hcd xhci-pci hid usbhid hid-generic)
die() { echo "guest-image: $*" >&2; exit 1; }
[ -x /bin/busybox ] || die "busybox-static is not installed (scripts/setup installs it)"
command -v cpio >/dev/null || die "cpio is not installed (scripts/setup installs it)"

mkdir -p "$cache"
if [ ! -f "$cache/vmlinuz" ] || [ ! -d "$cache/modules" ]; then
  pkg=$(apt-cache depends linux-image-amd64 2>/dev/null | sed -n 's/^ *Depends: \(linux-image-[0-9].*-amd64\)$/\1/p' | head -1)
  [ -n "$pkg" ] || die "apt-cache does not know linux-image-amd64 (run apt-get update)"
  tmp=$(mktemp -d "$cache/download.XXXX")
  echo "guest-image: downloading $pkg (once, into $cache)" >&2
  # apt's _apt user cannot write into a private folder: download from a world-writable one.
  (cd "$tmp" && chmod 777 . && apt-get download -q "$pkg" >/dev/null 2>"$tmp/apt.log") ||
    { cat "$tmp/apt.log" >&2; rm -rf "$tmp"; die "could not download $pkg (offline?)"; }
  dpkg-deb -x "$tmp"/*.deb "$tmp/root"
  cp "$tmp"/root/boot/vmlinuz-* "$cache/vmlinuz.new"
  rm -rf "$cache/modules" && mkdir -p "$cache/modules"
  for m in "${modules[@]}"; do
    f=$(find "$tmp/root/lib/modules" -name "$m.ko" -o -name "$m.ko.xz" | head -1)
    [ -n "$f" ] || die "module $m not in $pkg"
    case $f in *.xz) xz -dc "$f" > "$cache/modules/$m.ko" ;; *) cp "$f" "$cache/modules/$m.ko" ;; esac
    # Every dependency must come earlier in the list.
    deps=$(tr '\0' '\n' < "$cache/modules/$m.ko" | sed -n 's/^depends=//p' | tr ',' ' ')
    for d in $deps; do [ -f "$cache/modules/$d.ko" ] || die "module $m needs $d, which is not loaded before it"; done
  done
  mv "$cache/vmlinuz.new" "$cache/vmlinuz"
  rm -rf "$tmp"
fi

root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
mkdir -p "$root"/{bin,sbin,proc,sys,dev,tmp,lib/modules,run}
cp /bin/busybox "$root/bin/busybox"
for tool in sh mount insmod mkdir cat ls echo sleep poweroff grep sed seq find readlink hexdump od dd timeout; do
  ln -s busybox "$root/bin/$tool"
done
cp "$cache"/modules/*.ko "$root/lib/modules/"
cp "$script" "$root/guest-test.sh"
chmod +x "$root/guest-test.sh"
# copy_libs FILE: the shared libraries FILE needs, at the paths the loader looks for them.
copy_libs() {
  { ldd "$1" 2>/dev/null || true; } | awk '/=> \//{print $3} /^\t\/lib/{print $1}' | while read -r lib; do
    mkdir -p "$root$(dirname "$lib")"
    cp -L "$lib" "$root$lib"
  done
}
for f in "$@"; do
  if [[ $f == *=* ]]; then
    src=${f%%=*} dst=${f#*=}
    mkdir -p "$root$(dirname "$dst")"
    case $src in
      *.so) strip -o "$root$dst" "$src"; copy_libs "$src" ;;  # a module hmp loads: with its libraries
      *) cp "$src" "$root$dst" ;;
    esac
    continue
  fi
  mkdir -p "$root/opt/bin"
  strip -o "$root/opt/bin/$(basename "$f")" "$f"
  copy_libs "$f"
done
cat > "$root/init" <<INIT
#!/bin/sh
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
for m in ${modules[*]}; do insmod /lib/modules/\$m.ko || echo "guest: insmod \$m failed"; done
export PATH=/opt/bin:/bin
/guest-test.sh
echo "guest: exit \$?"
poweroff -f
INIT
chmod +x "$root/init"
(cd "$root" && find . | cpio -o -H newc --quiet) > "$out"
