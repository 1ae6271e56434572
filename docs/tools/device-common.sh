# Shared by the device-machine scripts beside it (sourced after `bin`, `out` and `debs` are
# set): unpacks the packages the machine lacks, points the Vulkan loader at NVIDIA's driver,
# records the machine in `$out/machine.txt` and logs the GPU's clocks to `$out/clocks.csv`
# every 250 ms from a background process whose pid is `$clocks`.
mkdir -p "$out"
if [ -n "$debs" ]; then
    for f in "$debs"/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -f "$icd" ]; then
    export VK_DRIVER_FILES=$icd
fi
export RUST_BACKTRACE=0
{
    date -u
    uname -a
    nvidia-smi --query-gpu=name,driver_version,clocks.max.sm,clocks.max.mem,power.limit \
        --format=csv 2>&1
    nproc
} >"$out/machine.txt" 2>&1
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.gr,clocks.mem,power.draw,temperature.gpu,utilization.gpu \
    --format=csv -lms 250 >"$out/clocks.csv" 2>&1 &
clocks=$!
