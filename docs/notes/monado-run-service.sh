#!/bin/sh
# usage: run-service.sh  (runs inside chroot)
export XRT_COMPOSITOR_NULL=1 SIMULATED_ENABLE=1 XRT_NO_STDIN=1 XDG_RUNTIME_DIR=/run/xrt
exec monado-service
