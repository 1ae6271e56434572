#!/usr/bin/env bash
# Calibrates the GPU cost model on a real GPU (`vr-ocean gpu-budget --calibrate`), as run on a
# lent device machine (docs/notes/gpu-cost-model.md): the calibration passes and the standard
# views at the Quest 2 eye size, with the specular anti-aliasing on (the headsets' default) and
# off, and at the Quest 3 eye size and settings; the Khronos validation layer on, the GPU's
# clocks logged while it runs.
#
# Usage: gpu-calibration.sh BINARY OUT_DIR [DEBS_DIR]
#   BINARY    a vr-ocean built on the CI machine (x86-64; `objcopy --strip-debug` keeps it
#             small enough to carry)
#   OUT_DIR   where the reports, logs and clock traces go
#   DEBS_DIR  Debian packages to unpack first where the machine lacks them (the Vulkan loader,
#             the validation layer, ALSA's library): `apt-get download libvulkan1
#             vulkan-validationlayers libasound2 libasound2-data` on the CI machine
set -u
bin=${1:?usage: gpu-calibration.sh BINARY OUT_DIR [DEBS_DIR]}
out=${2:?usage: gpu-calibration.sh BINARY OUT_DIR [DEBS_DIR]}
debs=${3:-}
# shellcheck source=device-common.sh
. "$(dirname "${BASH_SOURCE[0]}")/device-common.sh"
status=0
timeout 240 "$bin" gpu-budget --calibrate --validation --threads 8 \
    --report "$out/calibration-aa.json" >"$out/calibration-aa.txt" 2>&1 || status=$?
timeout 150 "$bin" gpu-budget --calibrate --validation --threads 8 --no-specular-aa \
    --report "$out/calibration-no-aa.json" >"$out/calibration-no-aa.txt" 2>&1 || status=$?
timeout 150 "$bin" gpu-budget --calibrate --validation --threads 8 --headset quest3 \
    --report "$out/calibration-q3.json" >"$out/calibration-q3.txt" 2>&1 || status=$?
kill "$clocks" 2>/dev/null
tail -n 12 "$out"/calibration-*.txt
exit "$status"
