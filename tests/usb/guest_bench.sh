#!/bin/sh
# Runs inside the USB guest for the usb-e2e benchmark (tools/bench/usb-e2e.sh): waits for the device's
# hidraw node, then runs the measuring program on it.
for i in $(seq 100); do [ -e /dev/hidraw0 ] && break; sleep 0.1; done
echo "guest: $(bench_usb_e2e_guest /dev/hidraw0 2>&1)"
