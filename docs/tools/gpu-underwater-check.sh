#!/usr/bin/env bash
# One device-machine check for issue 45 (docs/notes/gpu-cost-model.md): the GPU cost model
# asked to predict the device it runs on with the shaders as they are now (`gpu-budget
# --calibrate` at the Quest 2 eye size, the headsets' specular AA), and the view from under
# the water drawn by a GPU's multiview with MSAA 4 and the Khronos validation layer on: looking
# up and level from 4 m under, the eye at the mean level, and 30 s of a 15 m/s sea crossing a
# standing eye half a metre above the mean level. The GPU's clocks are logged meanwhile.
#
# Usage: gpu-underwater-check.sh BINARY OUT_DIR [DEBS_DIR]  (as gpu-calibration.sh)
set -u
bin=${1:?usage: gpu-underwater-check.sh BINARY OUT_DIR [DEBS_DIR]}
out=${2:?usage: gpu-underwater-check.sh BINARY OUT_DIR [DEBS_DIR]}
debs=${3:-}
# shellcheck source=device-common.sh
. "$(dirname "${BASH_SOURCE[0]}")/device-common.sh"
status=0
paths=$(mktemp -d)
shot() { # name height pitch wind frames capture
    printf '0 0 %s 0 0 %s\n' "$2" "$3" >"$paths/$1.path"
    timeout 120 "$bin" headless --validation --msaa 4 --wind "$4" --frames "$5" --capture "$6" \
        --size 960x960 --format jpeg --path "$paths/$1.path" --out "$out/$1" \
        >"$out/$1.txt" 2>&1 || status=$?
}
shot up -4 89.9 2 8 7
shot level -4 0 2 8 7
shot line 0 0 0.5 8 7
shot storm 0.5 0 15 2160 300,600,900,1200,1500,1800,2100
timeout 240 "$bin" gpu-budget --calibrate --validation --threads 8 \
    --report "$out/calibration-aa.json" >"$out/calibration-aa.txt" 2>&1 || status=$?
kill "$clocks" 2>/dev/null
grep -h -i -c "vuid\|validation error" "$out"/*.txt
tail -n 14 "$out"/calibration-aa.txt "$out"/storm.txt
exit "$status"
