#!/usr/bin/env bash
# Test qemu_boot_firmware: boots the firmware image with no host on the UART and the option
# exit-idle-ms=200; it must start, tick at its rate, send its periodic Status (UART frames) and exit 0
# after 200 ms without input, with a summary; the same with link=net over the Ethernet controller (QEMU
# gives the board its LAN9118 with nothing behind it), and with a host sending it frames that are not
# ours, which it must count and drop. An unknown option must stop it with exit code 4.
# Usage: check_firmware_boot.sh IMAGE.elf
set -uo pipefail
image=${1:?usage: check_firmware_boot.sh IMAGE.elf}
here=$(dirname "${BASH_SOURCE[0]}")
command -v "${QEMU_SYSTEM_ARM:-qemu-system-arm}" >/dev/null || { echo "FAIL: qemu-system-arm not installed"; exit 1; }
fail() { echo "FAIL: $*"; exit 1; }

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1000 exit-idle-ms=200" </dev/null 2>&1)
code=$?
printf '%s\n' "$out"
[ $code -eq 0 ] || fail "image exited with $code"
grep -q '^HMP qemu-an386 firmware .* tick_hz=1000 trace=off exit_idle_ms=200 listen_after_ms=0 link=uart$' <<<"$out" ||
  fail "banner"
summary=$(grep '^core:' <<<"$out") || fail "no summary"
ticks=$(sed -n 's/.* ticks=\([0-9]*\).*/\1/p' <<<"$summary")
[ "$ticks" = 200 ] || fail "expected 200 ticks before the idle exit, got '$ticks'"
# Idle, the core sends a Status every 100 ticks: two frames went out.
grep -q '^link: .*tx_frames=2 tx_dropped=0' <<<"$out" || fail "expected 2 Status frames on the UART"

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1000 exit-idle-ms=200 link=net" \
  </dev/null 2>&1)
code=$?
printf '%s\n' "$out"
[ $code -eq 0 ] || fail "image with link=net exited with $code"
grep -q '^HMP qemu-an386 firmware .* link=net$' <<<"$out" || fail "banner with link=net"
grep -q '^net: rx_frames=0 rx_foreign=0 rx_held=0 tx_frames=2 tx_dropped=0' <<<"$out" ||
  fail "expected 2 Status frames from the Ethernet controller"

# Frames that are not ours are counted and dropped: once the board has sent its first Status (its
# controller is up), a host sends one of another EtherType, one of ours but short, and one of ours whole
# (a zero report, refused by the core). Virtual time follows real time here (no sleep=off), so the idle
# exit waits for the host.
out=$(timeout 30 python3 - "$image" "${QEMU_SYSTEM_ARM:-qemu-system-arm}" <<'PY' 2>&1
import os, socket, subprocess, sys, tempfile
image, qemu = sys.argv[1], sys.argv[2]
device, host = bytes([2, 72, 77, 80, 0, 1]), bytes([2, 72, 77, 80, 0, 2])
with tempfile.TemporaryDirectory() as d:
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(d + "/host.sock")
    sock.settimeout(10)
    net = f"dgram,id=net0,local.type=unix,local.path={d}/nic.sock,remote.type=unix,remote.path={d}/host.sock"
    qemu_run = subprocess.Popen([qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "null",
                                 "-semihosting-config", "enable=on,target=native", "-icount", "shift=0",
                                 "-netdev", net, "-net", "nic,netdev=net0,model=lan9118", "-kernel", image,
                                 "-append", "hz=1000 exit-idle-ms=300 link=net"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    first = sock.recv(2048)
    print(f"host: first frame {len(first)} bytes, EtherType {first[12]:02x}{first[13]:02x}")
    for frame in (device + host + bytes([8, 0]) + bytes(64), device + host + bytes([0x88, 0xB5]) + bytes(56),
                  device + host + bytes([0x88, 0xB5]) + bytes(64)):
        sock.sendto(frame, d + "/nic.sock")
    print(qemu_run.communicate(timeout=20)[0], end="")
    sys.exit(qemu_run.returncode)
PY
)
code=$?
printf '%s\n' "$out"
[ $code -eq 0 ] || fail "image with link=net and a host sending foreign frames exited with $code"
grep -q '^host: first frame 78 bytes, EtherType 88b5$' <<<"$out" || fail "no Status frame reached the host"
grep -q '^net: rx_frames=3 rx_foreign=2 ' <<<"$out" || fail "expected 3 frames received, 2 of them foreign"
grep -q '^core: .* packets=1 rejected=1 ' <<<"$out" || fail "expected the whole frame's report at the core, refused"

out=$(timeout 20 "$here/run.sh" "$image" -serial null -monitor none -append "hz=1234567" </dev/null 2>&1)
code=$?
[ $code -eq 4 ] || { printf '%s\n' "$out"; fail "a bad option should exit 4, got $code"; }
grep -q '^bad option: hz=1234567' <<<"$out" || fail "bad option not named"
echo "qemu_boot_firmware: ok"
