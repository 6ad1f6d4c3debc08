#!/bin/sh
# Runs inside the Linux guest (busybox sh) of tests/usb/guest_test.sh: what the guest's own kernel made of
# our USB device, then hmp through hidraw. Every check prints "guest: ok NAME" or "guest: FAIL NAME: …";
# the host side (guest_test.sh) counts them, checks the play log, and pulls the device out when asked
# ("guest: unplug now") and plugs it back ("guest: replug now").
fail=0
check() {  # NAME GOT WANT
  if [ "$2" = "$3" ]; then echo "guest: ok $1"; else echo "guest: FAIL $1: got '$2', want '$3'"; fail=1; fi
}
centis() { sed 's/^\([0-9]*\)\.\([0-9]*\) .*/\1\2/' /proc/uptime; }
wait_for() {  # PATH: up to 10 s
  for i in $(seq 100); do [ -e "$1" ] && return 0; sleep 0.1; done
  return 1
}
export HOME=/tmp

wait_for /dev/hidraw0 || echo "guest: FAIL hidraw: no /dev/hidraw0 within 10 s"
d=/sys/bus/usb/devices/1-1
check idVendor "$(cat $d/idVendor)" 1209
check idProduct "$(cat $d/idProduct)" 0001
check manufacturer "$(cat $d/manufacturer)" "Haptic Music Player project"
check product "$(cat $d/product)" "Haptic Music Player SPIDAR-G6 controller"
check serial "$(cat $d/serial)" "USBSIM0001"
check bMaxPacketSize0 "$(cat $d/bMaxPacketSize0)" 64
check bNumConfigurations "$(cat $d/bNumConfigurations)" 1
check bNumInterfaces "$(cat $d/bNumInterfaces | tr -d ' ')" 1
check speed "$(cat $d/speed)" 12
i=$d/1-1:1.0
check bInterfaceClass "$(cat $i/bInterfaceClass)" 03
check bNumEndpoints "$(cat $i/bNumEndpoints)" 02
check interface_driver "$(basename "$(readlink $i/driver)")" usbhid
for ep in 81:in 01:out; do
  e=$i/ep_${ep%%:*}
  check "ep_${ep%%:*}" "$(cat $e/type) $(cat $e/direction) $(cat $e/wMaxPacketSize) $(cat $e/bInterval)" "Interrupt ${ep##*:} 0040 01"
done
h=$(ls -d /sys/bus/hid/devices/0003:1209:0001.* | head -1)
check hid_driver "$(basename "$(readlink $h/driver)")" hid-generic
# HIDIOCGRDESC's bytes, as the kernel keeps them (the same buffer the ioctl copies out).
check report_descriptor "$(od -An -tx1 -v $h/report_descriptor | tr -d ' \n')" \
  "0600ff0901a101150026ff00750895400901810209019102c0"

out=$(hmp devices 2>&1)
echo "$out" | sed 's/^/guest: devices: /'
case $out in *1209:0001*0.1.0*) echo "guest: ok hmp_devices" ;; *) echo "guest: FAIL hmp_devices"; fail=1 ;; esac

echo "guest: play begin"
hmp play /opt/data/song.mid --track flute --device hid --no-audio --no-view --from 30 --to 40 --log /tmp/play.log \
  > /tmp/play.out 2>&1
rc=$?
sed 's/^/guest: play: /' /tmp/play.out
check play_exit "$rc" 0
echo "guest: log begin"
cat /tmp/play.log
echo "guest: log end"

# Unplugged mid-song with --exit-on-device-loss (for scripts): hmp says so and exits 1 within a second.
hmp play /opt/data/song.mid --track flute --device hid --no-audio --no-view --from 30 --exit-on-device-loss \
  > /tmp/unplug.out 2>&1 &
pid=$!
sleep 2
echo "guest: unplug now"
for i in $(seq 100); do [ -e /dev/hidraw0 ] || break; sleep 0.02; done
gone=$(centis)
wait $pid
rc=$?
ended=$(centis)
sed 's/^/guest: unplugged: /' /tmp/unplug.out
check unplug_exit "$rc" 1
took=$((ended - gone))
if [ "$took" -le 100 ]; then echo "guest: ok unplug_within_1s (${took}0 ms)"; else echo "guest: FAIL unplug_within_1s: ${took}0 ms"; fail=1; fi
case $(cat /tmp/unplug.out) in *device*) echo "guest: ok unplug_said" ;; *) echo "guest: FAIL unplug_said"; fail=1 ;; esac

echo "guest: replug now"
wait_for /dev/hidraw0 || echo "guest: FAIL replug: no /dev/hidraw0 within 10 s"
sleep 0.5
case $(hmp devices 2>&1) in *1209:0001*) echo "guest: ok replug_found" ;; *) echo "guest: FAIL replug_found"; fail=1 ;; esac

# Unplugged mid-song by default: hmp pauses, waits, and plays on when the device is back; the host side
# checks the log (every note after the resume on its tick).
hmp play /opt/data/song.mid --track flute --device hid --no-audio --no-view --from 30 --to 40 --log /tmp/resume.log \
  > /tmp/resume.out 2>&1 &
pid=$!
sleep 3
echo "guest: unplug now"
for i in $(seq 100); do [ -e /dev/hidraw0 ] || break; sleep 0.02; done
sleep 1
echo "guest: replug now"
wait $pid
rc=$?
sed 's/^/guest: resumed: /' /tmp/resume.out
check resume_exit "$rc" 0
case $(cat /tmp/resume.out) in *"device lost — plug it back in, or q to quit"*) echo "guest: ok resume_said_lost" ;;
  *) echo "guest: FAIL resume_said_lost"; fail=1 ;; esac
case $(cat /tmp/resume.out) in *"is back: playing on at"*) echo "guest: ok resume_said_back" ;;
  *) echo "guest: FAIL resume_said_back"; fail=1 ;; esac
echo "guest: resume log begin"
cat /tmp/resume.log
echo "guest: resume log end"
echo "guest: done fail=$fail"
